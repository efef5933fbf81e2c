/* OBJ export of a rig: DIR/neutral.obj and one full-shape OBJ per ARKit-named blendshape
 * (neutral + delta, the rig's vertex order, the source polygons with their UVs and
 * materials), plus DIR/frig.mtl with the materials' diffuse colours. Metres. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/buffer.h"
#include "io/file.h"
#include "rig/rig.h"

#define MTL_NAME "frig.mtl"

/* The vt and f lines, the same in every file. */
static void write_faces(const fr_topology *t, fr_buffer *b) {
    for (int i = 0; i < t->uv_count; i++) fr_buffer_printf(b, "vt %.7g %.7g\n", t->uvs[2 * i], t->uvs[2 * i + 1]);
    int material = -1;
    for (int p = 0; p < t->polygon_count; p++) {
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

static frig_status write_shape(frig_ctx *ctx, const char *dir, const char *name, const frig_rig *rig,
                               const float *delta, const fr_buffer *faces) {
    fr_buffer b = {0};
    fr_buffer_printf(&b, "# libfrig %s: %s (metres)\nmtllib %s\n", frig_version_string(), name, MTL_NAME);
    const float *n = rig->neutral;
    for (int i = 0; i < rig->topo.vertex_count; i++) {
        const float *d = delta ? delta + 3 * i : NULL;
        fr_buffer_printf(&b, "v %.7g %.7g %.7g\n", d ? n[3 * i] + d[0] : n[3 * i], d ? n[3 * i + 1] + d[1] : n[3 * i + 1],
                         d ? n[3 * i + 2] + d[2] : n[3 * i + 2]);
    }
    fr_buffer_append(&b, faces->data, faces->size);
    char file[96];
    snprintf(file, sizeof file, "%s.obj", name);
    char *path = fr_path_join(dir, file);
    frig_status s = b.failed || !path ? fr_nomem(ctx, "an OBJ file") : fr_write_file_atomic(ctx, path, b.data, b.size);
    free(path);
    fr_buffer_free(&b);
    return s;
}

static frig_status write_mtl(frig_ctx *ctx, const char *dir, const fr_topology *t) {
    fr_buffer b = {0};
    fr_buffer_printf(&b, "# libfrig %s\n", frig_version_string());
    for (int m = 0; m < t->material_count; m++) {
        const float *kd = t->material_kd + 3 * m;
        fr_buffer_printf(&b, "newmtl %s\nKd %.6g %.6g %.6g\nKa 0 0 0\nKs 0.05 0.05 0.05\nNs 18\nillum 2\n\n",
                         t->material_names[m], kd[0], kd[1], kd[2]);
    }
    char *path = fr_path_join(dir, MTL_NAME);
    frig_status s = b.failed || !path ? fr_nomem(ctx, "the MTL file") : fr_write_file_atomic(ctx, path, b.data, b.size);
    free(path);
    fr_buffer_free(&b);
    return s;
}

frig_status frig_rig_save_obj(frig_ctx *ctx, const frig_rig *rig, const char *dir) {
    if (!rig || !dir) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_save_obj: NULL rig or folder");
    frig_status s = fr_make_dirs(ctx, dir);
    if (s) return s;
    fr_export_shapes shapes;
    if ((s = fr_export_shapes_make(ctx, rig, &shapes))) return s;
    fr_buffer faces = {0};
    write_faces(&rig->topo, &faces);
    if (faces.failed) s = fr_nomem(ctx, "OBJ faces");
    if (!s) s = write_mtl(ctx, dir, &rig->topo);
    if (!s) s = write_shape(ctx, dir, "neutral", rig, NULL, &faces);
    size_t n3 = 3 * (size_t)rig->topo.vertex_count;
    /* Files are independent: write them in parallel, keep the first failure in order. */
    frig_status *st = calloc((size_t)shapes.count + 1, sizeof *st);
    if (!s && !st) s = fr_nomem(ctx, "OBJ export");
    if (!s) {
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
        for (int k = 0; k < shapes.count; k++)
            st[k] = write_shape(ctx, dir, shapes.names[k], rig, shapes.deltas + n3 * (size_t)k, &faces);
        for (int k = 0; k < shapes.count && !s; k++) s = st[k];
    }
    free(st);
    fr_buffer_free(&faces);
    fr_export_shapes_free(&shapes);
    return s;
}
