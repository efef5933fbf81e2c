/* Expression weights given the blendshapes (paper section 5.2.3 (b)): per photo a bounded
 * least-squares problem in [0, 1] (Li et al. 2010 solve the same), over the vertices the
 * shapes move. The k x k matrices of all photos come from one BLAS-3 product of the vertices'
 * packed D_v^T D_v with the photos' coverage; each problem is then solved exactly by the box
 * QP of the fit stage. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <omp.h>

#include "core/context.h"
#include "linalg/box_qp.h"
#include "model/mode_sums.h"
#include "retarget/retarget.h"

#define MOVING 1e-4 /* metres: a vertex no shape moves more than this carries no weight information */
#define BLOCK 256   /* moving vertices per product of the photos' k x k matrices */

/* The packed lower triangle of D_v^T D_v for one vertex's k deltas side by side (dv: 3 k floats). */
static void pack_gram(const float *dv, int k, double *g) {
    int q = 0;
    for (int c = 0; c < k; c++)
        for (int r = c; r < k; r++) {
            const float *dr = dv + 3 * r, *dc = dv + 3 * c;
            g[q++] = (double)dr[0] * dc[0] + (double)dr[1] * dc[1] + (double)dr[2] * dc[2];
        }
}

frig_status fr_rt_fit_weights(frig_ctx *ctx, const fr_rt_settings *s, int nv, int k, const float *neutral,
                              const float *D, int n, fr_rt_photo *photos) {
    if (k == 0 || n == 0) return FRIG_OK;
    size_t n3 = 3 * (size_t)nv;
    int P = k * (k + 1) / 2;
    /* Each vertex's k deltas side by side (Dv: 3 k floats per vertex), then the vertices some
     * shape moves. */
    int *vert = malloc(sizeof(int) * ((size_t)nv + 1)), nm = 0;
    float *Dv = malloc(sizeof(float) * n3 * (size_t)k + 1);
    if (!vert || !Dv) {
        free(vert), free(Dv);
        return fr_nomem(ctx, "the expression weights");
    }
    fr_modes_by_vertex(D, (size_t)nv, k, Dv);
    for (int v = 0; v < nv; v++) {
        double big = 0;
        for (int q = 0; q < 3 * k; q++) big = fmax(big, fabs(Dv[3 * (size_t)v * k + q]));
        if (big > MOVING) vert[nm++] = v;
    }
    double *G = malloc(sizeof(double) * (size_t)P * BLOCK);
    double *C = malloc(sizeof(double) * ((size_t)nm * n + 1));
    double *H = malloc(sizeof(double) * (size_t)P * ((size_t)n + 1));
    double *Dd = malloc(sizeof(double) * n3 * (size_t)k);
    size_t per_thread = (size_t)k * k + 3 * (size_t)k + n3;
    double *work = malloc(sizeof(double) * per_thread * (size_t)s->threads);
    frig_status st = G && C && H && Dd && work ? FRIG_OK : fr_nomem(ctx, "the expression weights");
    if (st) goto done;
    for (size_t q = 0; q < n3 * (size_t)k; q++) Dd[q] = D[q];
    for (int i = 0; i < n; i++)
        for (int a = 0; a < nm; a++) C[(size_t)i * nm + a] = photos[i].cover[vert[a]];
    if (nm == 0) memset(H, 0, sizeof(double) * (size_t)P * n);
    int saved = fr_blas_serial_begin();
    /* H = G C over blocks of moving vertices, G[:, a] = packed lower D_v^T D_v of moving vertex a:
     * a block's G is made and multiplied in a buffer used again (the whole G, P x nm doubles, is
     * about 90 MB for 50 shapes, each page of it written once). */
    for (int a0 = 0; a0 < nm; a0 += BLOCK) {
        int nb = nm - a0 < BLOCK ? nm - a0 : BLOCK;
        for (int b = 0; b < nb; b++) pack_gram(Dv + 3 * (size_t)vert[a0 + b] * k, k, G + (size_t)P * b);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, P, n, nb, 1.0, G, P, C + a0, nm, a0 ? 1.0 : 0.0, H, P);
    }
    int failed = 0;
#pragma omp parallel for schedule(dynamic) num_threads(s->threads)
    for (int i = 0; i < n; i++) {
        fr_rt_photo *p = &photos[i];
        double *S = work + per_thread * (size_t)omp_get_thread_num(), *g = S + (size_t)k * k, *lo = g + k, *hi = lo + k;
        double *r = hi + k;
        double observed = 0;
        for (int v = 0; v < nv; v++) observed += p->cover[v];
        if (observed <= 0) continue; /* no data: the weights stay */
        const double *h = H + (size_t)P * i;
        int q = 0;
        for (int c = 0; c < k; c++)
            for (int rr = c; rr < k; rr++) {
                S[(size_t)c * k + rr] = h[q];
                S[(size_t)rr * k + c] = h[q++];
            }
        /* r = c (M' - N) on the moving vertices, 0 elsewhere; g = -D^T r. */
        memset(r, 0, sizeof(double) * n3);
        for (int a = 0; a < nm; a++) {
            int v = vert[a];
            for (int c = 0; c < 3; c++)
                r[3 * (size_t)v + c] = p->cover[v] * ((double)p->M[3 * (size_t)v + c] - neutral[3 * (size_t)v + c]);
        }
        cblas_dgemv(CblasColMajor, CblasTrans, (int)n3, k, -1.0, Dd, (int)n3, r, 1, 0.0, g, 1);
        double ridge = s->weights_prior * observed * 1e-6, l1 = s->weights_sparse * observed * 1e-6;
        for (int j = 0; j < k; j++) {
            S[(size_t)j * k + j] += ridge + 1e-12;
            g[j] += l1 - ridge * p->w[j];
            lo[j] = 0, hi[j] = 1;
        }
        if (fr_box_qp(NULL, k, S, g, lo, hi, p->w) != FRIG_OK) failed = 1;
    }
    fr_blas_serial_end(saved);
    if (failed) st = fr_error(ctx, FRIG_ERR_NUMERIC, "an expression weight problem is not positive definite");
done:
    free(vert), free(Dv), free(G), free(C), free(H), free(Dd), free(work);
    return st;
}
