/* Holding the face's size (model/face_size.h, docs/fit.md "The head's size"):
 * the size gradient against the face's actual size under small identity
 * changes, the constrained solve against its optimality conditions, and the
 * fit's joint identity keeping the mean face's size while the landmarks of a
 * larger or smaller face are fitted. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "fit/fit_model.h"
#include "fit/progressive_fit.h"
#include "frig/synth.h"
#include "model/face_size.h"
#include "model_fixture.h"
#include "testing.h"

#define FACE 9409

static unsigned long long rng = 777;
static double uniform(void) {
    rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* RMS distance of the face region's vertices from their centroid. */
static double face_size(const float *v) {
    double c[3] = {0, 0, 0}, s = 0;
    for (int i = 0; i < FACE; i++)
        for (int k = 0; k < 3; k++)
            c[k] += v[3 * i + k] / FACE;
    for (int i = 0; i < FACE; i++)
        for (int k = 0; k < 3; k++)
            s += (v[3 * i + k] - c[k]) * (v[3 * i + k] - c[k]);
    return sqrt(s / FACE);
}

static double size_ratio(frig_ctx *ctx, const frig_model *m, const double *w, int n_id) {
    int nv = frig_model_vertex_count(m);
    float *a = malloc(sizeof(float) * 3 * (size_t)nv), *b = malloc(sizeof(float) * 3 * (size_t)nv);
    double *full = calloc((size_t)frig_model_identity_count(m), sizeof(double));
    double r = 0;
    if (a && b && full) {
        memcpy(full, w, sizeof(double) * (size_t)n_id);
        frig_model_eval(ctx, m, NULL, NULL, a);
        frig_model_eval(ctx, m, full, NULL, b);
        r = face_size(b) / face_size(a);
    }
    free(a), free(b), free(full);
    return r;
}

static void test_gradient(frig_ctx *ctx, const frig_model *m) {
    int n = 100;
    double g[100], w[100];
    CHECK(fr_face_size_gradient(ctx, m, n, g) == FRIG_OK);
    double norm = 0;
    for (int i = 0; i < n; i++)
        norm += g[i] * g[i];
    printf("size gradient: |g| = %.4f (relative size per standard deviation, all "
           "modes)\n",
           sqrt(norm));
    CHECK(norm > 1e-8);
    for (int trial = 0; trial < 3; trial++) {
        for (int i = 0; i < n; i++)
            w[i] = 0.05 * (2 * uniform() - 1);
        double predicted = 0;
        for (int i = 0; i < n; i++)
            predicted += g[i] * w[i];
        double actual = size_ratio(ctx, m, w, n) - 1;
        printf("  identity of 0.05 sd per mode: size change %.6f, first order %.6f\n", actual, predicted);
        CHECK(fabs(actual - predicted) < 0.05 * fabs(predicted) + 1e-5);
    }
    /* Along the gradient itself, a change of 2% (second-order terms stay small).
     */
    for (int i = 0; i < n; i++)
        w[i] = 0.02 * g[i] / norm;
    CHECK_NEAR(size_ratio(ctx, m, w, n), 1.02, 0.002);
}

/* x = argmin x'Hx/2 - b'x subject to g'(w - x) = 0: the constraint holds and Hx
 * - b is parallel to g (the KKT conditions). */
static void test_solve(frig_ctx *ctx) {
    enum { N = 12 };
    double A[N * N], H[N * N], b[N], x[N], w[N], g[N];
    for (int i = 0; i < N * N; i++)
        A[i] = 2 * uniform() - 1;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            double s = i == j ? N : 0;
            for (int k = 0; k < N; k++)
                s += A[k * N + i] * A[k * N + j];
            H[i * N + j] = s;
        }
    for (int i = 0; i < N; i++)
        b[i] = 2 * uniform() - 1, w[i] = 2 * uniform() - 1, g[i] = 2 * uniform() - 1;
    double Hc[N * N];
    memcpy(Hc, H, sizeof H);
    memcpy(x, b, sizeof b);
    double gw0 = 0;
    for (int i = 0; i < N; i++)
        gw0 += g[i] * w[i];
    CHECK(fr_solve_size_held(ctx, N, Hc, x, g, gw0) == FRIG_OK);
    double gw = 0, gg = 0, r[N], rg = 0;
    for (int i = 0; i < N; i++)
        gw += g[i] * (w[i] - x[i]), gg += g[i] * g[i];
    CHECK(fabs(gw) < 1e-12);
    for (int i = 0; i < N; i++) {
        r[i] = -b[i];
        for (int j = 0; j < N; j++)
            r[i] += H[i * N + j] * x[j];
        rg += r[i] * g[i];
    }
    double off = 0; /* the part of Hx - b not along g */
    for (int i = 0; i < N; i++)
        off += pow(r[i] - rg / gg * g[i], 2);
    CHECK(sqrt(off) < 1e-10);
}

/* Landmarks of a synthetic subject whose face is 6% larger than its identity's
 * (the whole head scaled about the origin, then photographed): with the size
 * held the joint identity keeps the mean face's size (the camera's distance
 * takes the scale); without, it follows the landmarks toward the larger face.
 */
static void test_fit_holds_size(frig_ctx *ctx, const frig_model *m) {
    fr_fit_model fm;
    CHECK(fr_fit_model_build(ctx, m, 100, &fm) == FRIG_OK);
    frig_synth_subject *subj = NULL;
    CHECK(frig_synth_subject_create(ctx, m, 4100, &subj) == FRIG_OK);
    if (!subj)
        return;
    enum { PHOTOS = 10 };
    fr_fit_input in[PHOTOS];
    double lm[PHOTOS][136];
    memset(in, 0, sizeof in);
    for (int p = 0; p < PHOTOS; p++) {
        frig_image *img = NULL;
        frig_synth_truth *tr = NULL;
        CHECK(frig_synth_render(ctx, subj, 91000 + (uint64_t)p, FRIG_SYNTH_FAILURE_NONE, &img, &tr) == FRIG_OK);
        if (!tr)
            return;
        const double *q = frig_synth_truth_landmarks(tr, 1);
        /* 6% larger about the image centre: a larger head at the same distance. */
        double cx = 0.5 * frig_image_width(img), cy = 0.5 * frig_image_height(img);
        for (int k = 0; k < 68; k++)
            lm[p][2 * k] = cx + 1.06 * (q[2 * k] - cx), lm[p][2 * k + 1] = cy + 1.06 * (q[2 * k + 1] - cy);
        in[p].landmarks = lm[p];
        in[p].width = frig_image_width(img);
        in[p].height = frig_image_height(img);
        frig_image_free(img);
        frig_synth_truth_free(tr);
    }
    fr_fit_settings st;
    fr_fit_settings_from_ctx(ctx, &st);
    CHECK(st.mean_size == 0); /* the default */
    double *w = calloc((size_t)PHOTOS * fm.n_cols, sizeof(double)), identity[100], ratio[2];
    fr_fit_result res[PHOTOS];
    for (int held = 1; held >= 0 && w; held--) {
        st.mean_size = held;
        for (int p = 0; p < PHOTOS; p++)
            res[p].w = w + (size_t)p * fm.n_cols;
        CHECK(fr_fit_run(ctx, &fm, &st, FR_SCHEME_PROGRESSIVE, PHOTOS, in, res, identity) == FRIG_OK);
        double gw = 0;
        for (int i = 0; i < fm.n_id; i++)
            gw += fm.size_gradient[i] * identity[i];
        ratio[held] = size_ratio(ctx, m, identity, fm.n_id);
        printf("fit.mean_size %d: fitted face %.4f x the mean face's size (first "
               "order %.2e)\n",
               held, ratio[held], gw);
        if (held)
            CHECK(fabs(gw) < 1e-9);
    }
    double truth = face_size(frig_rig_neutral(frig_synth_subject_rig(subj)));
    float *mean = malloc(sizeof(float) * 3 * (size_t)frig_model_vertex_count(m));
    if (mean) {
        frig_model_eval(ctx, m, NULL, NULL, mean);
        printf("the subject's true face: %.4f x the mean face's size\n", truth / face_size(mean));
    }
    CHECK(fabs(ratio[1] - 1) < 0.005);
    free(mean);
    free(w);
    frig_synth_subject_free(subj);
    fr_fit_model_free(&fm);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_solve(ctx);
    frig_model *m = fixture_model(ctx);
    if (!m) {
        frig_ctx_free(ctx);
        return test_skip("the ICT-FaceKit model (../shared/ict-facekit) is not available");
    }
    frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_IMAGE_SIZE, 320);
    frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_MAX_YAW, 40);
    test_gradient(ctx, m);
    test_fit_holds_size(ctx, m);
    frig_model_free(m);
    frig_ctx_free(ctx);
    return test_result("test_face_size");
}
