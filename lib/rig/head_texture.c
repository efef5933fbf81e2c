/* The back of the head's base colour (ICT's M_BackHead: scalp, back of the ears, the neck's base
 * and the shoulders). The face texture ends where M_Face meets M_BackHead; one flat colour there
 * (the seam's mean) left a line wherever the texture's colour along the seam differs from its
 * mean (the neck's base in every render). Here every vertex the two materials share takes the face
 * texture's colour at its face UV, the rest of M_BackHead the harmonic extension of those colours
 * (the cotangent Laplacian of the neutral over M_BackHead's triangles, the shared vertices as the
 * boundary: smooth, equal to the face's colour along the seam, the seam's average far from it),
 * baked into M_BackHead's UV tile. Linear light throughout; the texels stored as sRGB. */
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
 * face corners. Returns the number of seam vertices and their mean colour in mean[3]. */
static int seam_colours(const fr_topology *t, int face, const uint8_t *on_head, const fr_texture *face_tex,
                        double *rgb, int *corners, float mean[3]) {
    float decode[256];
    fr_srgb_decode_table(decode);
    for (int i = 0; i < t->triangle_count; i++) {
        if (t->triangle_materials[i] != face) continue;
        for (int c = 0; c < 3; c++) {
            int v = t->triangles[3 * i + c];
            if (!on_head[v]) continue;
            const float *uv = t->uvs + 2 * t->triangle_uvs[3 * i + c];
            double rgba[4];
            fr_texture_sample_linear(face_tex, decode, uv[0], uv[1], rgba);
            for (int k = 0; k < 3; k++) rgb[3 * (size_t)v + k] += rgba[k];
            corners[v]++;
        }
    }
    int n = 0;
    double sum[3] = {0, 0, 0};
    for (int v = 0; v < t->vertex_count; v++) {
        if (!corners[v]) continue;
        for (int k = 0; k < 3; k++) rgb[3 * (size_t)v + k] /= corners[v], sum[k] += rgb[3 * (size_t)v + k];
        n++;
    }
    for (int k = 0; k < 3; k++) mean[k] = n ? (float)(sum[k] / n) : 0.0f;
    return n;
}

frig_status fr_head_texture_paint(frig_ctx *ctx, const frig_rig *rig, int face, int head, const fr_texture *face_tex,
                                  int size, fr_texture *out) {
    memset(out, 0, sizeof *out);
    const fr_topology *t = &rig->topo;
    size_t nv = (size_t)t->vertex_count, n = (size_t)size * (size_t)size;
    uint8_t *on_head = calloc(nv + 1, 1), *covered = malloc(n), *free_vertex = malloc(nv + 1);
    int *corners = calloc(nv + 1, sizeof *corners), nt = 0;
    double *rgb = calloc(3 * nv + 1, sizeof *rgb);
    for (int i = 0; i < t->triangle_count; i++) nt += t->triangle_materials[i] == head;
    int32_t *tris = malloc(sizeof(int32_t) * 3 * ((size_t)nt + 1));
    float *attr = malloc(sizeof(float) * (3 * nv + 1)), *baked = malloc(sizeof(float) * 3 * n);
    out->pixels = malloc(3 * n);
    frig_status s = !on_head || !covered || !free_vertex || !corners || !rgb || !tris || !attr || !baked || !out->pixels
                        ? fr_nomem(ctx, "the head's texture")
                        : FRIG_OK;
    float mean[3];
    int seam = 0;
    if (!s) {
        mark_material(t, head, on_head);
        seam = seam_colours(t, face, on_head, face_tex, rgb, corners, mean);
    }
    if (!s && seam) {
        for (int i = 0, k = 0; i < t->triangle_count; i++)
            if (t->triangle_materials[i] == head) memcpy(tris + 3 * (size_t)k++, t->triangles + 3 * (size_t)i, sizeof(int32_t) * 3);
        for (size_t v = 0; v < nv; v++) {
            free_vertex[v] = !corners[v];
            for (int c = 0; c < 3; c++) attr[3 * v + (size_t)c] = (float)rgb[3 * v + (size_t)c];
        }
        s = fr_harmonic_extend(ctx, (int)nv, rig->neutral, tris, nt, free_vertex, 1, MEAN_PULL, mean, attr);
    }
    for (size_t i = 0; !s && seam && i < 3 * nv; i++) /* cotangent weights may overshoot a little */
        attr[i] = attr[i] < 0 ? 0.0f : attr[i] > 1 ? 1.0f : attr[i];
    if (!s && seam) s = fr_texture_bake(ctx, t, head, attr, 3, size, baked, covered);
    for (size_t i = 0; !s && seam && i < 3 * n; i++) {
        double c = fr_linear_to_srgb(baked[i] < 0 ? 0 : baked[i] > 1 ? 1 : baked[i]);
        out->pixels[i] = (uint8_t)floor(255.0 * c + 0.5);
    }
    if (!s && seam) {
        out->width = out->height = size;
        out->channels = 3;
        snprintf(out->file, sizeof out->file, "frig_head.png");
        s = fr_png_encode_pixels(ctx, size, size, 3, 3 * (size_t)size, out->pixels, &out->png, &out->png_size);
    }
    free(on_head), free(covered), free(free_vertex), free(corners), free(rgb), free(tris), free(attr), free(baked);
    if (s || !seam) fr_texture_free(out); /* no seam: no texture, the head keeps its flat colour */
    return s;
}
