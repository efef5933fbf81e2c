/* Pictures of a rig for people who would rather look than read: the neutral or any mix of
 * blendshapes rendered by libfrig's own rasterizer with the look the exporters write (look.c:
 * painted eyes, the face texture or clay), and a contact sheet of every exported shape. Three
 * passes per picture: opaque materials; alpha-masked ones (the sclera, whose cornea shows the
 * iris behind it) in front of them where their alpha is at least 1/2; then the blended eye
 * overlays composited over the result in a fixed order. Lit by a key, a fill and a rim light
 * with a little Blinn-Phong specular, in linear light, 3x supersampled, sRGB-encoded. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "image/srgb.h"
#include "raster/draw.h"
#include "raster/raster.h"
#include "rig/look.h"
#include "rig/rig.h"

#define SUPERSAMPLE 3
#define MARGIN 0.08 /* of the framed box, each side */

/* One pass's triangles: their vertex indices and which rig triangle each is. */
typedef struct pass {
    int nt;
    int32_t *tris, *ids;
} pass;

typedef struct scene {
    const frig_rig *rig;
    const fr_rig_look *look;
    int nv;
    float *xc, *normals; /* camera frame, 3 per vertex */
    fr_camera cam;
    int w, h;          /* supersampled size */
    float decode[256]; /* 8-bit sRGB code -> linear */
} scene;

static void pass_free(pass *p) {
    free(p->tris);
    free(p->ids);
    memset(p, 0, sizeof *p);
}

/* Triangles whose material has alpha mode 'mode' (and, for blended ones, material m only). */
static frig_status pass_make(frig_ctx *ctx, const frig_rig *rig, const fr_rig_look *look, int mode, int material,
                             pass *p) {
    const fr_topology *t = &rig->topo;
    memset(p, 0, sizeof *p);
    p->tris = malloc(sizeof(int32_t) * 3 * (size_t)(t->triangle_count + 1));
    p->ids = malloc(sizeof(int32_t) * (size_t)(t->triangle_count + 1));
    if (!p->tris || !p->ids) {
        pass_free(p);
        return fr_nomem(ctx, "a render pass");
    }
    for (int i = 0; i < t->triangle_count; i++) {
        int m = t->triangle_materials[i];
        const fr_material_look *l = &look->materials[m];
        if (l->omitted || l->alpha_mode != mode || (material >= 0 && m != material)) continue;
        memcpy(p->tris + 3 * (size_t)p->nt, t->triangles + 3 * (size_t)i, sizeof(int32_t) * 3);
        p->ids[p->nt++] = i;
    }
    return FRIG_OK;
}

static void normalize3(double v[3]) {
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0.0)
        for (int i = 0; i < 3; i++) v[i] /= l;
}

/* Linear colour (specular included), alpha and the specular alone of the surface at raster
 * pixel px of a pass. */
static void shade(const scene *sc, const fr_raster *r, const pass *ps, size_t px, int x, int y, double out[5]) {
    const fr_topology *t = &sc->rig->topo;
    int tri = ps->ids[r->tri[px]];
    const float *b = r->bary + 3 * px;
    const fr_material_look *l = &sc->look->materials[t->triangle_materials[tri]];
    double n[3] = {0, 0, 0}, uv[2] = {0, 0};
    for (int c = 0; c < 3; c++) {
        int32_t v = t->triangles[3 * tri + c];
        const float *tc = t->uvs + 2 * t->triangle_uvs[3 * tri + c];
        for (int k = 0; k < 3; k++) n[k] += b[c] * sc->normals[3 * (size_t)v + k];
        uv[0] += b[c] * tc[0], uv[1] += b[c] * tc[1];
    }
    normalize3(n);
    double view[3] = {(x - sc->cam.cx) / sc->cam.f, (y - sc->cam.cy) / sc->cam.f, 1.0};
    normalize3(view);
    if (n[0] * view[0] + n[1] * view[1] + n[2] * view[2] > 0.0) /* seen from behind: light the side we see */
        for (int k = 0; k < 3; k++) n[k] = -n[k];
    double albedo[4] = {l->base[0], l->base[1], l->base[2], l->base[3]};
    if (l->texture >= 0) {
        double tex[4];
        fr_texture_sample_linear(&sc->look->textures[l->texture], sc->decode, uv[0], uv[1], tex);
        for (int k = 0; k < 4; k++) albedo[k] *= tex[k];
    }
    /* camera frame: x right, y down, z forward; directions toward each light */
    static const double lights[3][4] = {
        {-0.55, -0.65, -1.0, 1.05}, /* key: upper left, in front */
        {0.85, -0.10, -0.9, 0.35},  /* fill: right */
        {0.10, -1.00, 0.45, 0.35},  /* rim: above, behind */
    };
    double diffuse = 0.22, spec = 0.0;
    double ks = 0.5 * (1.0 - l->roughness) * (1.0 - l->roughness), shininess = 2.0 / fmax(0.01, l->roughness * l->roughness);
    for (int i = 0; i < 3; i++) {
        double L[3] = {lights[i][0], lights[i][1], lights[i][2]};
        normalize3(L);
        double nl = n[0] * L[0] + n[1] * L[1] + n[2] * L[2];
        if (nl <= 0.0) continue;
        diffuse += lights[i][3] * nl;
        double H[3] = {L[0] - view[0], L[1] - view[1], L[2] - view[2]};
        normalize3(H);
        double nh = n[0] * H[0] + n[1] * H[1] + n[2] * H[2];
        if (nh > 0.0) spec += lights[i][3] * ks * pow(nh, shininess);
    }
    for (int k = 0; k < 3; k++) out[k] = albedo[k] * diffuse + spec;
    out[3] = albedo[3];
    out[4] = spec;
}

static void background(int y, int h, double rgb[3]) {
    double t = (double)y / (h > 1 ? h - 1 : 1);
    static const double top[3] = {0.075, 0.080, 0.090}, bottom[3] = {0.025, 0.027, 0.031};
    for (int k = 0; k < 3; k++) rgb[k] = top[k] + (bottom[k] - top[k]) * t;
}

/* The whole picture into 'lin' (w * h * 3, linear, supersampled). */
static frig_status draw(frig_ctx *ctx, const scene *sc, float *lin) {
    const fr_topology *t = &sc->rig->topo;
    pass opaque = {0}, masked = {0};
    fr_raster *ro = NULL, *rm = NULL, *rb = NULL;
    frig_status s = pass_make(ctx, sc->rig, sc->look, FR_ALPHA_OPAQUE, -1, &opaque);
    if (!s) s = pass_make(ctx, sc->rig, sc->look, FR_ALPHA_MASK, -1, &masked);
    if (!s) s = fr_raster_create(ctx, sc->w, sc->h, &ro);
    if (!s) s = fr_raster_create(ctx, sc->w, sc->h, &rm);
    if (!s) s = fr_raster_create(ctx, sc->w, sc->h, &rb);
    fr_raster_options opt = {FR_RASTER_DEFAULT_NEAR, 0};
    if (!s) s = fr_raster_render(ctx, ro, &sc->cam, sc->xc, sc->nv, opaque.tris, opaque.nt, &opt);
    if (!s) s = fr_raster_render(ctx, rm, &sc->cam, sc->xc, sc->nv, masked.tris, masked.nt, &opt);
    float *depth = s ? NULL : malloc(sizeof(float) * (size_t)sc->w * (size_t)sc->h);
    if (!s && !depth) s = fr_nomem(ctx, "a render");
    for (int y = 0; !s && y < sc->h; y++)
        for (int x = 0; x < sc->w; x++) {
            size_t px = (size_t)y * (size_t)sc->w + (size_t)x;
            double c[5];
            background(y, sc->h, c);
            depth[px] = INFINITY;
            if (ro->tri[px] >= 0) shade(sc, ro, &opaque, px, x, y, c), depth[px] = ro->depth[px];
            if (rm->tri[px] >= 0 && rm->depth[px] < depth[px]) {
                double m[5];
                shade(sc, rm, &masked, px, x, y, m);
                if (m[3] >= 0.5) memcpy(c, m, sizeof(double) * 3), depth[px] = rm->depth[px];
                else
                    for (int k = 0; k < 3; k++) c[k] += m[4]; /* the clear cornea still reflects */
            }
            for (int k = 0; k < 3; k++) lin[3 * px + (size_t)k] = (float)c[k];
        }
    /* the blended overlays, one material at a time, over what is behind them */
    for (int m = 0; !s && m < t->material_count; m++) {
        const fr_material_look *l = &sc->look->materials[m];
        if (l->omitted || l->alpha_mode != FR_ALPHA_BLEND) continue;
        pass bp;
        s = pass_make(ctx, sc->rig, sc->look, FR_ALPHA_BLEND, m, &bp);
        if (!s && bp.nt) s = fr_raster_render(ctx, rb, &sc->cam, sc->xc, sc->nv, bp.tris, bp.nt, &opt);
        for (int y = 0; !s && bp.nt && y < sc->h; y++)
            for (int x = 0; x < sc->w; x++) {
                size_t px = (size_t)y * (size_t)sc->w + (size_t)x;
                if (rb->tri[px] < 0 || !(rb->depth[px] < depth[px])) continue;
                double c[5];
                shade(sc, rb, &bp, px, x, y, c);
                for (int k = 0; k < 3; k++) lin[3 * px + (size_t)k] += (float)(c[3] * (c[k] - lin[3 * px + (size_t)k]));
            }
        pass_free(&bp);
    }
    free(depth);
    fr_raster_free(ro);
    fr_raster_free(rm);
    fr_raster_free(rb);
    pass_free(&opaque);
    pass_free(&masked);
    return s;
}

/* The box the picture frames, in the model frame, from the neutral (so every picture of a
 * contact sheet is framed alike): the face region or the whole head. */
static void frame_box(const frig_rig *rig, int framing, double lo[3], double hi[3]) {
    int first = 0, count = rig->topo.vertex_count;
    if (framing == FRIG_FRAME_FACE && !fr_topology_region(&rig->topo, "narrow_face", &first, &count))
        first = 0, count = rig->topo.vertex_count;
    for (int d = 0; d < 3; d++) lo[d] = INFINITY, hi[d] = -INFINITY;
    for (int v = first; v < first + count; v++)
        for (int d = 0; d < 3; d++) {
            double x = rig->neutral[3 * (size_t)v + d];
            lo[d] = fmin(lo[d], x), hi[d] = fmax(hi[d], x);
        }
}

/* Pose and camera: the box's centre on the optical axis, far enough that its corners fit. */
static void place(const frig_rig *rig, double yaw, double pitch, int framing, int w, int h, double R[9], double tr[3],
                  fr_camera *cam) {
    double lo[3], hi[3], c[3];
    frame_box(rig, framing, lo, hi);
    for (int d = 0; d < 3; d++) c[d] = 0.5 * (lo[d] + hi[d]);
    fr_rotation_from_euler(yaw * M_PI / 180.0, pitch * M_PI / 180.0, 0.0, R);
    *cam = fr_camera_perspective(3.0 * (w > h ? w : h), w, h); /* about an 100 mm lens */
    double rc[3];
    fr_mat3_apply(R, c, rc);
    double need = 0.0;
    for (int corner = 0; corner < 8; corner++) {
        double p[3] = {corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]}, q[3];
        fr_mat3_apply(R, p, q);
        for (int d = 0; d < 3; d++) q[d] -= rc[d];
        /* the corner at depth z in front of the centre must project inside the margin */
        double ax = fabs(q[0]) / ((0.5 - MARGIN) * w / cam->f), ay = fabs(q[1]) / ((0.5 - MARGIN) * h / cam->f);
        need = fmax(need, fmax(ax, ay) - q[2]);
    }
    for (int d = 0; d < 3; d++) tr[d] = -rc[d];
    tr[2] += need;
}

/* Render positions xyz (model frame) into an RGB image of w x h. */
static frig_status render_xyz(frig_ctx *ctx, const frig_rig *rig, const fr_rig_look *look, const float *xyz,
                              double yaw, double pitch, int framing, int w, int h, frig_image **out) {
    *out = NULL;
    scene sc;
    memset(&sc, 0, sizeof sc);
    sc.rig = rig, sc.look = look, sc.nv = rig->topo.vertex_count;
    sc.w = w * SUPERSAMPLE, sc.h = h * SUPERSAMPLE;
    fr_srgb_decode_table(sc.decode);
    double R[9], tr[3];
    place(rig, yaw, pitch, framing, sc.w, sc.h, R, tr, &sc.cam);
    sc.xc = malloc(sizeof(float) * 6 * (size_t)sc.nv);
    float *lin = malloc(sizeof(float) * 3 * (size_t)sc.w * (size_t)sc.h);
    frig_image *img = fr_image_new(w, h, 3);
    frig_status s = !sc.xc || !lin || !img ? fr_nomem(ctx, "a render") : FRIG_OK;
    if (!s) {
        sc.normals = sc.xc + 3 * (size_t)sc.nv;
        fr_transform_points(R, tr, xyz, sc.nv, sc.xc);
        fr_mesh_vertex_normals(sc.xc, sc.nv, rig->topo.triangles, rig->topo.triangle_count, sc.normals);
        s = draw(ctx, &sc, lin);
    }
    for (int y = 0; !s && y < h; y++)
        for (int x = 0; x < w; x++)
            for (int k = 0; k < 3; k++) {
                double sum = 0.0;
                for (int j = 0; j < SUPERSAMPLE; j++)
                    for (int i = 0; i < SUPERSAMPLE; i++)
                        sum += lin[3 * ((size_t)(SUPERSAMPLE * y + j) * (size_t)sc.w + (size_t)(SUPERSAMPLE * x + i)) + (size_t)k];
                double v = fr_linear_to_srgb(sum / (SUPERSAMPLE * SUPERSAMPLE));
                img->pixels[(size_t)y * img->stride + 3 * (size_t)x + (size_t)k] = (uint8_t)floor(255.0 * v + 0.5);
            }
    free(sc.xc);
    free(lin);
    if (s) frig_image_free(img);
    else *out = img;
    return s;
}

static frig_status check_size(frig_ctx *ctx, const char *what, int w, int h) {
    if (w < 16 || h < 16 || w > 8192 || h > 8192)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: %d x %d pixels (16 to 8192 on a side)", what, w, h);
    return FRIG_OK;
}

frig_status frig_rig_render(frig_ctx *ctx, const frig_rig *rig, const double *weights, double yaw_deg,
                            double pitch_deg, int framing, int width, int height, frig_image **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_render: out is NULL");
    *out = NULL;
    if (!rig) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_render: no rig");
    frig_status s = check_size(ctx, "frig_rig_render", width, height);
    if (s) return s;
    if (!isfinite(yaw_deg) || !isfinite(pitch_deg))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_render: yaw and pitch must be finite");
    fr_rig_look look;
    if ((s = fr_rig_look_make(ctx, rig, &look))) return s;
    float *xyz = malloc(sizeof(float) * 3 * (size_t)rig->topo.vertex_count);
    if (!xyz) s = fr_nomem(ctx, "a render");
    if (!s && weights) s = frig_rig_eval(ctx, rig, weights, xyz);
    else if (!s) memcpy(xyz, rig->neutral, sizeof(float) * 3 * (size_t)rig->topo.vertex_count);
    if (!s) s = render_xyz(ctx, rig, &look, xyz, yaw_deg, pitch_deg, framing, width, height, out);
    free(xyz);
    fr_rig_look_free(&look);
    return s;
}

/* ---- the contact sheet ---- */

#define LABEL_SCALE 2

static void paste(frig_image *dst, const frig_image *src, int x0, int y0) {
    for (int y = 0; y < src->height; y++)
        memcpy(dst->pixels + (size_t)(y0 + y) * dst->stride + 3 * (size_t)x0, src->pixels + (size_t)y * src->stride,
               3 * (size_t)src->width);
}

/* The name centred under its picture; a name too long for one line is broken before the
 * capital letter nearest its middle (mouthLowerDown / Right). */
static void draw_label(frig_image *sheet, int x0, int y0, int cell, const char *name) {
    static const uint8_t grey[3] = {215, 215, 210};
    char line[2][96];
    int w, h, n = (int)strlen(name), split = -1;
    fr_text_size(name, LABEL_SCALE, &w, &h);
    const char *plus = strchr(name, '+');
    if (plus) split = (int)(plus - name); /* two shapes together: one per line */
    else if (w > cell)
        for (int i = 1; i < n; i++)
            if (name[i] >= 'A' && name[i] <= 'Z' && (split < 0 || abs(2 * i - n) < abs(2 * split - n))) split = i;
    snprintf(line[0], sizeof line[0], "%.*s", split > 0 ? split : n, name);
    snprintf(line[1], sizeof line[1], "%s", split > 0 ? name + split : "");
    for (int k = 0; k < 2 && line[k][0]; k++) {
        fr_text_size(line[k], LABEL_SCALE, &w, &h);
        int scale = w > cell ? 1 : LABEL_SCALE;
        fr_text_size(line[k], scale, &w, &h);
        fr_draw_text(sheet, x0 + (cell - w) / 2, y0 + k * (h + 3), line[k], scale, grey);
    }
}

frig_status frig_rig_save_contact_sheet(frig_ctx *ctx, const frig_rig *rig, int cell, int columns, const char *path) {
    if (!rig || !path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_save_contact_sheet: NULL argument");
    frig_status s = check_size(ctx, "a contact sheet cell", cell, cell);
    if (s) return s;
    if (columns < 1 || columns > 64)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a contact sheet of %d columns (1 to 64)", columns);
    fr_rig_look look;
    fr_export_shapes shapes;
    if ((s = fr_rig_look_make(ctx, rig, &look))) return s;
    if ((s = fr_export_shapes_make(ctx, rig, &shapes))) {
        fr_rig_look_free(&look);
        return s;
    }
    int n = shapes.count + 1, rows = (n + columns - 1) / columns, tw, th;
    fr_text_size("Xg", LABEL_SCALE, &tw, &th);
    int label_h = 2 * th + 11, gap = 4;
    int sheet_w = columns * cell + (columns + 1) * gap, sheet_h = rows * (cell + label_h) + (rows + 1) * gap;
    frig_image *sheet = fr_image_new(sheet_w, sheet_h, 3);
    frig_status *st = calloc((size_t)n, sizeof *st);
    if (!sheet || !st) s = fr_nomem(ctx, "a contact sheet");
    if (!s) memset(sheet->pixels, 28, sheet->stride * (size_t)sheet_h);
    size_t n3 = 3 * (size_t)rig->topo.vertex_count;
    /* mouthClose closes the lips of an open jaw (ARKit's and ICT's convention): alone it pushes the
     * lower lip up through the upper one, so its picture adds jawOpen */
    int jaw = -1, close = -1;
    for (int k = 0; k < shapes.count; k++) {
        if (!strcmp(shapes.names[k], "jawOpen")) jaw = k;
        if (!strcmp(shapes.names[k], "mouthClose")) close = k;
    }
    atomic_size_t done;
    atomic_init(&done, 0);
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
    for (int i = 0; i < n; i++) {
        if (s || fr_cancelled(ctx)) continue;
        frig_ctx child;
        fr_ctx_init_child(&child, ctx);
        float *xyz = malloc(sizeof(float) * n3);
        frig_image *img = NULL;
        st[i] = xyz ? FRIG_OK : fr_nomem(&child, "a contact sheet cell");
        if (!st[i]) {
            const float *d = i ? shapes.deltas + n3 * (size_t)(i - 1) : NULL;
            const float *with = jaw >= 0 && i - 1 == close ? shapes.deltas + n3 * (size_t)jaw : NULL;
            for (size_t k = 0; k < n3; k++) xyz[k] = (d ? rig->neutral[k] + d[k] : rig->neutral[k]) + (with ? with[k] : 0);
            st[i] = render_xyz(&child, rig, &look, xyz, 0.0, 0.0, FRIG_FRAME_FACE, cell, cell, &img);
        }
        if (!st[i]) {
            int col = i % columns, row = i / columns;
            int x0 = gap + col * (cell + gap), y0 = gap + row * (cell + label_h + gap);
            paste(sheet, img, x0, y0);
            draw_label(sheet, x0, y0 + cell + 4, cell,
                       !i ? "neutral" : jaw >= 0 && i - 1 == close ? "mouthClose+jawOpen" : shapes.names[i - 1]);
        } else {
            fr_error(ctx, st[i], "%s", frig_ctx_errmsg(&child));
        }
        frig_image_free(img);
        free(xyz);
        fr_progress_tick(ctx, &done, "contact_sheet", (size_t)n);
    }
    for (int i = 0; !s && i < n; i++) s = st[i];
    if (!s) s = fr_check_cancel(ctx, "the contact sheet");
    if (!s) s = frig_image_save_png(ctx, sheet, path);
    free(st);
    frig_image_free(sheet);
    fr_export_shapes_free(&shapes);
    fr_rig_look_free(&look);
    return s;
}
