/* OBJ export of a rig: DIR/neutral.obj and one full-shape OBJ per ARKit-named blendshape
 * (neutral + delta, the rig's vertex order, the source polygons with their UVs and
 * materials), plus DIR/frig.mtl with the look's colours, transparency and textures (the
 * PNGs written beside it: the face's base colour, the painted eyes). Metres. Overlays left
 * out (export.eye_overlays 0) lose their faces, not their vertices: ICT's indices stay. */
#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/context.h"
#include "io/buffer.h"
#include "io/file.h"
#include "rig/look.h"
#include "rig/rig.h"

#define MTL_NAME "frig.mtl"

/* The vt and f lines, the same in every file. */
static void write_faces(const fr_topology *t, const fr_rig_look *look, fr_buffer *b) {
    for (int i = 0; i < t->uv_count; i++) fr_buffer_printf(b, "vt %.7g %.7g\n", t->uvs[2 * i], t->uvs[2 * i + 1]);
    int material = -1;
    for (int p = 0; p < t->polygon_count; p++) {
        if (look->materials[t->poly_materials[p]].omitted) continue;
        if (t->poly_materials[p] != material) {
            material = t->poly_materials[p];
            fr_buffer_printf(b, "usemtl %s\n", t->material_names[material]);
        }
        fr_buffer_append(b, "f", 1);
        for (int c = t->poly_offsets[p]; c < t->poly_offsets[p + 1]; c++)
            fr_buffer_printf(b, " %d/%d", t->poly_corners[c] + 1, t->poly_uvs[c] + 1);
        fr_buffer_append(b, "\n", 1);
    }
}

/* The neutral's "v" lines, and where each vertex's line starts (vertex_count + 1 offsets). */
typedef struct neutral_lines {
    fr_buffer text;
    size_t *start;
} neutral_lines;

static int neutral_lines_make(const frig_rig *rig, neutral_lines *nl) {
    const float *n = rig->neutral;
    nl->text = (fr_buffer){0};
    nl->start = malloc(sizeof(size_t) * ((size_t)rig->topo.vertex_count + 1));
    if (!nl->start) return 0;
    for (int i = 0; i < rig->topo.vertex_count; i++) {
        nl->start[i] = nl->text.size;
        fr_buffer_printf(&nl->text, "v %.7g %.7g %.7g\n", n[3 * i], n[3 * i + 1], n[3 * i + 2]);
    }
    nl->start[rig->topo.vertex_count] = nl->text.size;
    return !nl->text.failed;
}

/* A shape's vertex lines: where the sum neutral + delta is the neutral's float bit for bit
 * (most vertices of most shapes), the neutral's line is copied instead of printed again. */
static void vertex_lines(const frig_rig *rig, const float *delta, const neutral_lines *nl, fr_buffer *b) {
    const float *n = rig->neutral;
    for (int i = 0; i < rig->topo.vertex_count; i++) {
        const float *v = n + 3 * i, *d = delta + 3 * i;
        float x[3] = {v[0] + d[0], v[1] + d[1], v[2] + d[2]};
        if (!memcmp(x, v, sizeof x))
            fr_buffer_append(b, nl->text.data + nl->start[i], nl->start[i + 1] - nl->start[i]);
        else
            fr_buffer_printf(b, "v %.7g %.7g %.7g\n", x[0], x[1], x[2]);
    }
}

static frig_status write_shape(frig_ctx *ctx, const char *dir, const char *name, const frig_rig *rig,
                               const float *delta, const neutral_lines *nl, const fr_buffer *faces) {
    fr_buffer b = {0};
    /* the neutral's size, and a tenth more for lines printed with other digits */
    fr_buffer_reserve(&b, 256 + nl->text.size + (delta ? nl->text.size / 10 : 0) + faces->size);
    fr_buffer_printf(&b, "# libfrig %s: %s (metres)\nmtllib %s\n", frig_version_string(), name, MTL_NAME);
    if (delta) vertex_lines(rig, delta, nl, &b);
    else fr_buffer_append(&b, nl->text.data, nl->text.size);
    fr_buffer_append(&b, faces->data, faces->size);
    char file[96];
    snprintf(file, sizeof file, "%s.obj", name);
    char *path = fr_path_join(dir, file);
    frig_status s = b.failed || !path ? fr_nomem(ctx, "an OBJ file") : fr_write_file_atomic(ctx, path, b.data, b.size);
    free(path);
    fr_buffer_free(&b);
    return s;
}

/* An earlier export's frig_*.png that this one does not write (other export.* options). */
static void remove_stale_textures(const char *dir, const fr_rig_look *look) {
    DIR *d = opendir(dir);
    if (!d) return;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        size_t n = strlen(e->d_name);
        if (strncmp(e->d_name, "frig_", 5) != 0 || n < 9 || strcmp(e->d_name + n - 4, ".png") != 0) continue;
        int ours = 0;
        for (int i = 0; i < look->texture_count; i++) ours |= strcmp(look->textures[i].file, e->d_name) == 0;
        char *path = ours ? NULL : fr_path_join(dir, e->d_name);
        if (path) unlink(path);
        free(path);
    }
    closedir(d);
}

static frig_status write_mtl(frig_ctx *ctx, const char *dir, const fr_topology *t, const fr_rig_look *look) {
    fr_buffer b = {0};
    fr_buffer_printf(&b, "# libfrig %s\n", frig_version_string());
    for (int m = 0; m < t->material_count; m++) {
        const fr_material_look *l = &look->materials[m];
        if (l->omitted) continue;
        fr_buffer_printf(&b, "newmtl %s\nKd %.6g %.6g %.6g\nKa 0 0 0\nKs 0.05 0.05 0.05\nNs 18\nillum 2\n",
                         t->material_names[m], l->base[0], l->base[1], l->base[2]);
        if (l->alpha_mode != FR_ALPHA_OPAQUE && l->texture < 0) fr_buffer_printf(&b, "d %.6g\n", l->base[3]);
        if (l->texture >= 0) {
            const fr_texture *tex = &look->textures[l->texture];
            fr_buffer_printf(&b, "map_Kd %s\n", tex->file);
            if (tex->channels == 4) fr_buffer_printf(&b, "map_d %s\n", tex->file);
        }
        fr_buffer_append(&b, "\n", 1);
    }
    char *path = fr_path_join(dir, MTL_NAME);
    frig_status s = b.failed || !path ? fr_nomem(ctx, "the MTL file") : fr_write_file_atomic(ctx, path, b.data, b.size);
    free(path);
    fr_buffer_free(&b);
    for (int i = 0; !s && i < look->texture_count; i++) {
        const fr_texture *tex = &look->textures[i];
        path = fr_path_join(dir, tex->file);
        s = path ? fr_write_file_atomic(ctx, path, tex->png, tex->png_size) : fr_nomem(ctx, "a texture file");
        free(path);
    }
    if (!s) remove_stale_textures(dir, look);
    return s;
}

frig_status frig_rig_save_obj(frig_ctx *ctx, const frig_rig *rig, const char *dir) {
    if (!rig || !dir) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_save_obj: NULL rig or folder");
    frig_status s = fr_make_dirs(ctx, dir);
    if (s) return s;
    fr_rig_look look;
    if ((s = fr_rig_look_make(ctx, rig, &look))) return s;
    fr_export_shapes shapes;
    if ((s = fr_export_shapes_make(ctx, rig, &shapes))) {
        fr_rig_look_free(&look);
        return s;
    }
    fr_buffer faces = {0};
    write_faces(&rig->topo, &look, &faces);
    neutral_lines nl;
    if (!neutral_lines_make(rig, &nl) || faces.failed) s = fr_nomem(ctx, "OBJ lines");
    if (!s) s = write_mtl(ctx, dir, &rig->topo, &look);
    if (!s) s = write_shape(ctx, dir, "neutral", rig, NULL, &nl, &faces);
    size_t n3 = 3 * (size_t)rig->topo.vertex_count;
    /* Files are independent: write them in parallel, keep the first failure in order. */
    frig_status *st = calloc((size_t)shapes.count + 1, sizeof *st);
    if (!s && !st) s = fr_nomem(ctx, "OBJ export");
    if (!s) {
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
        for (int k = 0; k < shapes.count; k++)
            st[k] = write_shape(ctx, dir, shapes.names[k], rig, shapes.deltas + n3 * (size_t)k, &nl, &faces);
        for (int k = 0; k < shapes.count && !s; k++) s = st[k];
    }
    free(st);
    free(nl.start);
    fr_buffer_free(&nl.text);
    fr_buffer_free(&faces);
    fr_export_shapes_free(&shapes);
    fr_rig_look_free(&look);
    return s;
}
