/* An albedo texture against a frig synth subject's painted albedo (albedo_error.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/sort.h"
#include "eval/albedo_error.h"
#include "image/image.h"
#include "image/srgb.h"
#include "mesh/topology.h"
#include "rig/rig.h"
#include "synth/synth.h"

#define FACE 9409 /* the face region's vertices */

/* The texture's linear colour at uv: its nearest texel, texel (x, y) at
 * uv = ((x + 0.5) / W, 1 - (y + 0.5) / H). */
static void texel(const frig_image *img, const float decode[256], double u, double v, double rgb[3]) {
    int w = frig_image_width(img), h = frig_image_height(img);
    int x = (int)floor((u - floor(u)) * w), y = (int)floor((1.0 - (v - floor(v))) * h);
    x = x < 0 ? 0 : x >= w ? w - 1 : x, y = y < 0 ? 0 : y >= h ? h - 1 : y;
    const uint8_t *p = frig_image_pixels(img) + (size_t)y * frig_image_stride(img) + 3 * (size_t)x;
    for (int c = 0; c < 3; c++) rgb[c] = decode[p[c]];
}

/* ours and truth (3 per vertex, n vertices): the scale, then each vertex's error into err. */
static void score(const double *ours, const double *truth, int n, double *err, fr_albedo_error *out) {
    double mean_len = 0;
    for (int c = 0; c < 3; c++) {
        double num = 0, den = 0, m = 0;
        for (int i = 0; i < n; i++) {
            num += ours[3 * i + c] * truth[3 * i + c], den += ours[3 * i + c] * ours[3 * i + c];
            m += truth[3 * i + c] / n;
        }
        out->scale[c] = den > 0 ? num / den : 0;
        mean_len += m * m;
    }
    mean_len = sqrt(mean_len);
    double sum = 0;
    int gross = 0;
    for (int i = 0; i < n; i++) {
        double d2 = 0;
        for (int c = 0; c < 3; c++) {
            double d = out->scale[c] * ours[3 * i + c] - truth[3 * i + c];
            d2 += d * d;
        }
        err[i] = mean_len > 0 ? sqrt(d2) / mean_len : 0;
        sum += err[i];
        gross += err[i] > FR_ALBEDO_GROSS;
    }
    qsort(err, (size_t)n, sizeof(double), fr_cmp_double);
    out->vertices = n;
    out->mean = n ? sum / n : 0;
    out->p90 = n ? err[(n * 9) / 10] : 0;
    out->p99 = n ? err[(n * 99) / 100] : 0;
    out->gross = n ? (double)gross / n : 0;
}

frig_status fr_albedo_error_of(frig_ctx *ctx, const frig_synth_subject *subject, const frig_image *texture,
                               fr_albedo_error *out) {
    memset(out, 0, sizeof *out);
    if (frig_image_channels(texture) != 3)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_albedo_error_of: the texture has %d channels, not 3",
                        frig_image_channels(texture));
    const fr_topology *t = &subject->rig->topo;
    int nv = subject->nv, nf = nv < FACE ? nv : FACE;
    int *uv_of = malloc(sizeof(int) * ((size_t)nv + 1));
    double *ours = malloc(sizeof(double) * 3 * ((size_t)nf + 1)), *truth = malloc(sizeof(double) * 3 * ((size_t)nf + 1));
    double *err = malloc(sizeof(double) * ((size_t)nf + 1));
    if (!uv_of || !ours || !truth || !err) {
        free(uv_of), free(ours), free(truth), free(err);
        return fr_nomem(ctx, "the albedo's error");
    }
    float decode[256];
    fr_srgb_decode_table(decode);
    /* each vertex's UV in the face's layout: the first face-skin triangle corner that names it */
    for (int v = 0; v < nv; v++) uv_of[v] = -1;
    for (int i = 0; i < t->triangle_count; i++)
        for (int c = 0; c < 3 && fr_topology_face_skin(t, i); c++)
            if (uv_of[t->triangles[3 * i + c]] < 0) uv_of[t->triangles[3 * i + c]] = t->triangle_uvs[3 * i + c];
    int n = 0;
    for (int v = 0; v < nf; v++) {
        if (!subject->skin[v] || subject->hair[v] > 0.1f || uv_of[v] < 0) continue;
        const float *uv = t->uvs + 2 * (size_t)uv_of[v];
        texel(texture, decode, uv[0], uv[1], ours + 3 * (size_t)n);
        for (int c = 0; c < 3; c++) truth[3 * (size_t)n + c] = subject->albedo[3 * (size_t)v + c];
        n++;
    }
    score(ours, truth, n, err, out);
    free(uv_of), free(ours), free(truth), free(err);
    return FRIG_OK;
}
