/* Specular highlights taken out of a photo's skin pixels before the stage reads their shading (beyond
 * the paper: its section 5.1.3 leaves highlights to the region selection of eq. 5.15, after the lighting,
 * the albedo, the registration and the shared shape have read them; docs/sfs.md, "Highlights").
 *
 * The dichromatic reflection model (Shafer, "Using color to separate reflection components", 1985): a
 * pixel is the body reflection, the albedo's colour times the shading, plus the surface reflection in the
 * light's colour, white in a white-balanced photo. Skin's body colour has one chroma d up to its tone
 * (the per-channel median chromaticity of the photo's skin pixels), so each skin pixel I splits by least
 * squares into k d + s (1, 1, 1); the white share 3 s / sum(I) is how much whiter than the skin it is.
 * Skin's own chroma varies from pixel to pixel (blotches, stubble, the redder shadows of subsurface
 * light, a video's compressed colour), so only a share well above the photo's usual spread is taken for
 * a highlight: more than sfs.highlights robust standard deviations above the median share, and only
 * where skin plus white explains the pixel to within 10% (a highlight under a warm lamp is not white:
 * taking white out of it left orange patches on a Bing photo of Will Smith). There all of s is taken
 * out. A photo whose skin chroma is spread wide (measured: a studio-lit video, the share's robust
 * deviation about 0.5) loses nothing; frig synth's skin (one chroma, Blinn-Phong highlights of 3-15% of
 * the key light) loses its highlights. */
#include <math.h>
#include <stdlib.h>

#include "core/context.h"
#include "core/select.h"
#include "sfs/sfs_highlights.h"

#define CHROMA_FLOOR 1e-3  /* linear sum of the channels below which a pixel's chroma is not read */
#define MIN_SKIN 50        /* skin pixels needed for the skin's chroma and the shares' spread */
#define MIN_CHROMA_DEG 3.0 /* the skin's chroma at least this far from grey (else no highlight can be told) */
#define MAX_RESIDUAL 0.1   /* what skin plus white leaves of a pixel, at most, for its white part to go */

int fr_sfs_skin_chroma(const fr_sfs_view *v, double d[3]) {
    size_t n = (size_t)v->w * v->h, m = 0;
    float *ch = malloc(sizeof(float) * 3 * (n + 1));
    if (!ch) return -1;
    for (size_t i = 0; i < n; i++) {
        if (!v->skin[i]) continue;
        const float *I = v->I + 3 * i;
        double sum = (double)I[0] + I[1] + I[2];
        if (!(sum > CHROMA_FLOOR)) continue;
        for (int c = 0; c < 3; c++) ch[(size_t)c * n + m] = (float)(I[c] / sum);
        m++;
    }
    double len = 0;
    for (int c = 0; c < 3 && m >= MIN_SKIN; c++) {
        d[c] = fr_select_float(ch + (size_t)c * n, m, m / 2);
        len += d[c] * d[c];
    }
    free(ch);
    if (m < MIN_SKIN || !(len > 0)) return 0;
    for (int c = 0; c < 3; c++) d[c] /= sqrt(len);
    return 1;
}

/* The white part s of a colour I split by least squares into k d + s (1, 1, 1), d a unit chroma not
 * grey (k into *k). */
static double white_part(const double d[3], const float I[3], double *k) {
    /* the normal equations of I = k d + s w, w = (1, 1, 1): d.d = 1, w.w = 3 */
    double dw = d[0] + d[1] + d[2], det = 3.0 - dw * dw;
    double dI = d[0] * I[0] + d[1] * I[1] + d[2] * I[2], wI = (double)I[0] + I[1] + I[2];
    *k = (3.0 * dI - dw * wI) / det;
    return (wI - dw * dI) / det;
}

/* Whether skin plus white, k d + s (1, 1, 1), explains I to within MAX_RESIDUAL of its length: a
 * highlight under a coloured light, or a colour skin does not have, is not taken for white. */
static int white_explains(const double d[3], const float I[3], double s, double k) {
    double r2 = 0, i2 = 0;
    for (int c = 0; c < 3; c++) {
        double r = I[c] - k * d[c] - s;
        r2 += r * r, i2 += (double)I[c] * I[c];
    }
    return r2 <= MAX_RESIDUAL * MAX_RESIDUAL * i2;
}

/* The white share of skin pixel i, or NAN where it has no colour to read. */
static double white_share(const fr_sfs_view *v, const double d[3], size_t i, double *s, double *k) {
    const float *I = v->I + 3 * i;
    double sum = (double)I[0] + I[1] + I[2];
    if (!(sum > CHROMA_FLOOR)) return NAN;
    *s = white_part(d, I, k);
    return 3.0 * *s / sum;
}

frig_status fr_sfs_take_out_highlights(frig_ctx *ctx, fr_sfs_view *v, double nsig, int *changed) {
    *changed = 0;
    if (!(nsig > 0)) return FRIG_OK;
    double d[3];
    int got = fr_sfs_skin_chroma(v, d);
    if (got < 0) return fr_nomem(ctx, "the skin's chroma");
    if (!got || !((d[0] + d[1] + d[2]) / sqrt(3.0) < cos(MIN_CHROMA_DEG * M_PI / 180.0))) return FRIG_OK;
    size_t n = (size_t)v->w * v->h, m = 0;
    float *q = malloc(sizeof(float) * (n + 1));
    if (!q) return fr_nomem(ctx, "the highlights");
    for (size_t i = 0; i < n; i++) {
        double s, k, share = v->skin[i] ? white_share(v, d, i, &s, &k) : NAN;
        if (!isnan(share)) q[m++] = (float)share;
    }
    double limit = INFINITY;
    if (m >= MIN_SKIN) {
        float median = fr_select_float(q, m, m / 2);
        for (size_t j = 0; j < m; j++) q[j] = fabsf(q[j] - median);
        limit = median + nsig * 1.4826 * fr_select_float(q, m, m / 2);
    }
    free(q);
    for (size_t i = 0; i < n && isfinite(limit); i++) {
        double s, k, share = v->skin[i] ? white_share(v, d, i, &s, &k) : NAN;
        if (!(share > limit) || !(s > 0) || !(k > 0)) continue;
        float *I = v->I + 3 * i;
        if (!white_explains(d, I, s, k)) continue;
        for (int c = 0; c < 3; c++) I[c] = (float)fmax(0.0, I[c] - s);
        (*changed)++;
    }
    return FRIG_OK;
}
