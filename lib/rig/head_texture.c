/* The back of the head's base colour (ICT's M_BackHead: scalp, back of the ears, the neck's base
 * and the shoulders). The face texture ends where M_Face meets M_BackHead; one flat colour there
 * (the seam's mean) left a line wherever the texture's colour along the seam differs from its
 * mean (the neck's base in every render). Here every vertex the two materials share takes the face
 * texture's colour at its face UV, the rest of M_BackHead the harmonic extension of those colours
 * (the cotangent Laplacian of the neutral over M_BackHead's triangles, the shared vertices as the
 * boundary: smooth, equal to the face's colour along the seam, the seam's average far from it),
 * baked into M_BackHead's UV tile. Linear light throughout; the texels stored as sRGB. Without
 * painted textures (export.texture_size 0) the head keeps one flat colour, the seam's mean. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "image/srgb.h"
#include "mesh/harmonic_extension.h"
#include "rig/look.h"

/* A pull of every unknown toward the seam's mean colour (the cotangent Laplacian's diagonal is
 * of order 1 whatever the mesh's size): negligible where the seam is in reach, it gives any piece
 * of M_BackHead that does not touch the face that mean instead of leaving its system singular. */
#define MEAN_PULL 1e-6

/* Per rig vertex: 1 when a triangle of 'material' uses it. */
static void mark_material(const fr_topology *t, int material, uint8_t *on) {
    for (int i = 0; i < t->triangle_count; i++)
        if (t->triangle_materials[i] == material)
            for (int c = 0; c < 3; c++) on[t->triangles[3 * i + c]] = 1;
}

/* The linear colour of every seam vertex (on both materials): the mean of the face texture at its
 * face corners (corners[v] of them), sampled as the renderer samples it. Returns the number of seam
 * vertices; mean[3] gets the mean over all their corners. */
static int seam_colours(const fr_topology *t, int face, const uint8_t *on_head, const fr_texture *face_tex,
                        double *rgb, int *corners, float mean[3]) {
    float decode[256];
    fr_srgb_decode_table(decode);
    double sum[3] = {0, 0, 0};
    long all = 0;
    for (int i = 0; i < t->triangle_count; i++) {
        if (t->triangle_materials[i] != face) continue;
        for (int c = 0; c < 3; c++) {
            int v = t->triangles[3 * i + c];
            if (!on_head[v]) continue;
            const float *uv = t->uvs + 2 * t->triangle_uvs[3 * i + c];
            double rgba[4];
            fr_texture_sample_linear(face_tex, decode, uv[0], uv[1], rgba);
            for (int k = 0; k < 3; k++) rgb[3 * (size_t)v + k] += rgba[k], sum[k] += rgba[k];
            corners[v]++, all++;
        }
    }
    int n = 0;
    for (int v = 0; v < t->vertex_count; v++)
        if (corners[v]) {
            for (int k = 0; k < 3; k++) rgb[3 * (size_t)v + k] /= corners[v];
            n++;
        }
    for (int k = 0; all && k < 3; k++) mean[k] = (float)(sum[k] / (double)all);
    return n;
}

/* The texture: the seam's colours (attr, 3 per vertex, fixed where corners[v] > 0) extended
 * harmonically over the head's triangles, baked into its UV tile and encoded. */
static frig_status paint(frig_ctx *ctx, const frig_rig *rig, int head, const int *corners, const float mean[3],
                         int size, float *attr, fr_texture *out) {
    const fr_topology *t = &rig->topo;
    size_t nv = (size_t)t->vertex_count, n = (size_t)size * (size_t)size;
    int nt = 0;
    for (int i = 0; i < t->triangle_count; i++) nt += t->triangle_materials[i] == head;
    int32_t *tris = malloc(sizeof(int32_t) * 3 * ((size_t)nt + 1));
    uint8_t *free_vertex = malloc(nv + 1), *covered = malloc(n);
    float *baked = malloc(sizeof(float) * 3 * n);
    out->pixels = malloc(3 * n);
    frig_status s = !tris || !free_vertex || !covered || !baked || !out->pixels ? fr_nomem(ctx, "the head's texture")
                                                                                 : FRIG_OK;
    if (!s) {
        for (int i = 0, k = 0; i < t->triangle_count; i++)
            if (t->triangle_materials[i] == head) memcpy(tris + 3 * (size_t)k++, t->triangles + 3 * (size_t)i, sizeof(int32_t) * 3);
        for (size_t v = 0; v < nv; v++) free_vertex[v] = !corners[v];
        s = fr_harmonic_extend(ctx, (int)nv, rig->neutral, tris, nt, free_vertex, 1, MEAN_PULL, mean, attr);
    }
    for (size_t i = 0; !s && i < 3 * nv; i++) /* cotangent weights may overshoot a little */
        attr[i] = attr[i] < 0 ? 0.0f : attr[i] > 1 ? 1.0f : attr[i];
    if (!s) s = fr_texture_bake(ctx, t, head, attr, 3, size, baked, covered);
    for (size_t i = 0; !s && i < 3 * n; i++) {
        double c = fr_linear_to_srgb(baked[i] < 0 ? 0 : baked[i] > 1 ? 1 : baked[i]);
        out->pixels[i] = (uint8_t)floor(255.0 * c + 0.5);
    }
    if (!s) {
        out->width = out->height = size;
        out->channels = 3;
        snprintf(out->file, sizeof out->file, "frig_head.png");
        s = fr_png_encode_pixels(ctx, size, size, 3, 3 * (size_t)size, out->pixels, &out->png, &out->png_size);
    }
    free(tris), free(free_vertex), free(covered), free(baked);
    if (s) fr_texture_free(out);
    return s;
}

frig_status fr_head_look(frig_ctx *ctx, const frig_rig *rig, int face, int head, const fr_texture *face_tex, int size,
                         float flat[3], fr_texture *out) {
    memset(out, 0, sizeof *out);
    const fr_topology *t = &rig->topo;
    size_t nv = (size_t)t->vertex_count;
    uint8_t *on_head = calloc(nv + 1, 1);
    int *corners = calloc(nv + 1, sizeof *corners);
    double *rgb = calloc(3 * nv + 1, sizeof *rgb);
    float *attr = malloc(sizeof(float) * (3 * nv + 1));
    frig_status s = !on_head || !corners || !rgb || !attr ? fr_nomem(ctx, "the head's texture") : FRIG_OK;
    if (!s) {
        mark_material(t, head, on_head);
        float mean[3];
        if (seam_colours(t, face, on_head, face_tex, rgb, corners, mean)) {
            memcpy(flat, mean, sizeof mean);
            for (size_t i = 0; i < 3 * nv; i++) attr[i] = (float)rgb[i];
            if (size > 0) s = paint(ctx, rig, head, corners, mean, size, attr, out);
        }
    }
    free(on_head), free(corners), free(rgb), free(attr);
    return s;
}
