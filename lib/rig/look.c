/* The rig's look, shared by the glTF and OBJ writers and the renderer: what each of ICT's
 * materials is (by its name), its base colour, alpha mode and roughness, and its texture (the
 * face's base colour when one is set, the eye textures libfrig paints). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "image/srgb.h"
#include "rig/look.h"

fr_material_kind fr_material_kind_of(const char *name, int *eye) {
    static const struct {
        const char *name;
        fr_material_kind kind;
        int eye;
    } table[] = {
        {"M_Face", FR_MAT_FACE, -1},          {"M_BackHead", FR_MAT_HEAD, -1},
        {"M_GumsTongue", FR_MAT_MOUTH, -1},   {"M_Teeth", FR_MAT_TEETH, -1},
        {"M_ScleraLeft", FR_MAT_SCLERA, 0},   {"M_ScleraRight", FR_MAT_SCLERA, 1},
        {"M_IrisLeft", FR_MAT_IRIS, 0},       {"M_IrisRight", FR_MAT_IRIS, 1},
        {"M_LacrimalFluid", FR_MAT_LACRIMAL, -1}, {"M_EyeBlend", FR_MAT_EYE_BLEND, -1},
        {"M_EyeOcclusion", FR_MAT_EYE_OCCLUSION, -1}, {"M_EyeLashes", FR_MAT_LASHES, -1},
    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
        if (strcmp(table[i].name, name) == 0) {
            if (eye) *eye = table[i].eye;
            return table[i].kind;
        }
    if (eye) *eye = -1;
    return FR_MAT_OTHER;
}

static void set4(float *d, double r, double g, double b, double a) {
    d[0] = (float)r, d[1] = (float)g, d[2] = (float)b, d[3] = (float)a;
}

/* Untextured skin: a warm clay that shows the shape. */
#define CLAY_R 0.56
#define CLAY_G 0.42
#define CLAY_B 0.35

static void default_look(const fr_topology *t, int m, fr_material_look *l) {
    const float *kd = t->material_kd + 3 * m;
    l->kind = fr_material_kind_of(t->material_names[m], &l->eye);
    l->texture = -1;
    l->alpha_mode = FR_ALPHA_OPAQUE;
    l->roughness = 0.6f;
    set4(l->base, kd[0], kd[1], kd[2], 1.0);
    switch (l->kind) {
    case FR_MAT_FACE:
    case FR_MAT_HEAD: set4(l->base, CLAY_R, CLAY_G, CLAY_B, 1.0), l->roughness = 0.55f; break;
    case FR_MAT_MOUTH: l->roughness = 0.35f; break;
    case FR_MAT_TEETH: set4(l->base, 0.80, 0.76, 0.68, 1.0), l->roughness = 0.3f; break;
    case FR_MAT_SCLERA: set4(l->base, 0.83, 0.80, 0.76, 1.0), l->roughness = 0.15f; break;
    case FR_MAT_IRIS: set4(l->base, 0.12, 0.08, 0.05, 1.0), l->roughness = 0.4f; break;
    case FR_MAT_LACRIMAL: set4(l->base, 0.95, 0.95, 0.95, 0.12), l->alpha_mode = FR_ALPHA_BLEND, l->roughness = 0.05f; break;
    case FR_MAT_EYE_BLEND: set4(l->base, 0.55, 0.36, 0.32, 0.5), l->alpha_mode = FR_ALPHA_BLEND; break;
    case FR_MAT_EYE_OCCLUSION: set4(l->base, 0.01, 0.005, 0.004, 0.35), l->alpha_mode = FR_ALPHA_BLEND; break;
    case FR_MAT_LASHES: set4(l->base, 0.015, 0.012, 0.010, 1.0), l->double_sided = 1; break;
    default: break;
    }
}

/* The face texture, decoded. */
static frig_status face_texture(frig_ctx *ctx, const frig_rig *rig, fr_texture *tex) {
    frig_image *img = NULL;
    frig_status s = fr_png_decode(ctx, "the face texture", rig->face_png, rig->face_png_size, 0, &img);
    if (s) return s;
    memset(tex, 0, sizeof *tex);
    tex->width = img->width, tex->height = img->height, tex->channels = 3;
    tex->pixels = malloc(3 * (size_t)img->width * (size_t)img->height);
    tex->png = malloc(rig->face_png_size);
    if (!tex->pixels || !tex->png) {
        frig_image_free(img);
        fr_texture_free(tex);
        return fr_nomem(ctx, "the face texture");
    }
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            const uint8_t *p = img->pixels + (size_t)y * img->stride + (size_t)x * (size_t)img->channels;
            uint8_t *q = tex->pixels + 3 * ((size_t)y * (size_t)img->width + (size_t)x);
            for (int c = 0; c < 3; c++) q[c] = p[img->channels == 1 ? 0 : c];
        }
    frig_image_free(img);
    memcpy(tex->png, rig->face_png, rig->face_png_size);
    tex->png_size = rig->face_png_size;
    snprintf(tex->file, sizeof tex->file, "frig_face.png");
    return FRIG_OK;
}

static int has_texture(const fr_rig_look *look, int m) { return look->materials[m].texture >= 0; }

static int add_texture(fr_rig_look *look, fr_texture *t) {
    if (look->texture_count >= FR_LOOK_MAX_TEXTURES) {
        fr_texture_free(t);
        return -1;
    }
    look->textures[look->texture_count] = *t;
    return look->texture_count++;
}

frig_status fr_rig_look_make(frig_ctx *ctx, const frig_rig *rig, fr_rig_look *out) {
    memset(out, 0, sizeof *out);
    const fr_topology *t = &rig->topo;
    out->material_count = t->material_count;
    out->materials = calloc((size_t)t->material_count + 1, sizeof *out->materials);
    if (!out->materials) return fr_nomem(ctx, "the rig's materials");
    int face = -1, head = -1;
    for (int m = 0; m < t->material_count; m++) {
        default_look(t, m, &out->materials[m]);
        face = out->materials[m].kind == FR_MAT_FACE && face < 0 ? m : face;
        head = out->materials[m].kind == FR_MAT_HEAD && head < 0 ? m : head;
    }
    int overlays = fr_param_int(ctx, FRIG_PARAM_EXPORT_EYE_OVERLAYS), size = fr_param_int(ctx, FRIG_PARAM_EXPORT_TEXTURE_SIZE);
    frig_status s = FRIG_OK;
    if (rig->face_png && face >= 0) {
        fr_texture tex;
        s = face_texture(ctx, rig, &tex);
        if (!s) {
            fr_material_look *l = &out->materials[face];
            set4(l->base, 1, 1, 1, 1);
            l->texture = add_texture(out, &tex);
        }
        /* the back of the head continues the face: its texture, or (export.texture_size 0) the
         * seam's mean colour */
        float head_rgb[3] = {CLAY_R, CLAY_G, CLAY_B};
        fr_texture head_tex;
        if (!s && head >= 0 && has_texture(out, face) &&
            !(s = fr_head_look(ctx, rig, face, head, &out->textures[out->materials[face].texture], size, head_rgb,
                               &head_tex))) {
            fr_material_look *l = &out->materials[head];
            set4(l->base, head_rgb[0], head_rgb[1], head_rgb[2], 1.0);
            l->texture = head_tex.png ? add_texture(out, &head_tex) : -1;
            if (l->texture >= 0) set4(l->base, 1, 1, 1, 1);
        }
    }
    /* which materials get a painted texture, then paint them in parallel (each its own slot) */
    int want[64], nwant = 0;
    for (int m = 0; m < t->material_count; m++) {
        fr_material_look *l = &out->materials[m];
        int overlay = l->kind == FR_MAT_LACRIMAL || l->kind == FR_MAT_EYE_BLEND || l->kind == FR_MAT_EYE_OCCLUSION;
        if (overlay && !overlays) l->omitted = 1;
        int painted = l->kind == FR_MAT_SCLERA || l->kind == FR_MAT_IRIS || l->kind == FR_MAT_EYE_BLEND ||
                      l->kind == FR_MAT_EYE_OCCLUSION || l->kind == FR_MAT_LASHES;
        int first, count;
        if (!painted || l->omitted || size <= 0 || nwant == 64 ||
            out->texture_count + nwant >= FR_LOOK_MAX_TEXTURES)
            continue;
        if ((l->kind == FR_MAT_SCLERA || l->kind == FR_MAT_IRIS) &&
            !fr_topology_region(t, l->eye == 1 ? "eyeball_right" : "eyeball_left", &first, &count))
            continue; /* no eyeball to paint by: flat colours */
        want[nwant++] = m;
    }
    fr_texture tex[64];
    frig_status st[64];
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
    for (int i = 0; i < nwant; i++) {
        frig_ctx child;
        fr_ctx_init_child(&child, ctx);
        const fr_material_look *l = &out->materials[want[i]];
        st[i] = s ? s : fr_eye_texture_paint(&child, rig, want[i], l->kind, l->eye < 0 ? 0 : l->eye, size, &tex[i]);
        if (st[i]) fr_error(ctx, st[i], "%s", frig_ctx_errmsg(&child));
    }
    for (int i = 0; i < nwant; i++) {
        if (!s && st[i]) s = st[i];
        if (st[i]) continue;
        if (s) {
            fr_texture_free(&tex[i]);
            continue;
        }
        fr_material_look *l = &out->materials[want[i]];
        l->texture = add_texture(out, &tex[i]);
        set4(l->base, 1, 1, 1, 1);
        if (l->kind == FR_MAT_SCLERA) l->alpha_mode = FR_ALPHA_MASK;
        if (l->kind == FR_MAT_LASHES) l->alpha_mode = FR_ALPHA_BLEND;
    }
    if (s) fr_rig_look_free(out);
    return s;
}

void fr_rig_look_free(fr_rig_look *look) {
    if (!look) return;
    for (int i = 0; i < look->texture_count; i++) fr_texture_free(&look->textures[i]);
    free(look->materials);
    memset(look, 0, sizeof *look);
}
