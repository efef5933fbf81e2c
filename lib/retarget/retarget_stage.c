/* The retarget stage (paper section 5.2, Algorithm 6, eq. 5.16-5.17): on the face region,
 *   repeat: correspondences M'_i for every photo (Algorithm 7, correspondence.c);
 *           the neutral B_0 from eq. 5.16 with every blendshape free (w_d 1, w_t 0.5, w_m 0.01
 *           on B_0 only; the blendshapes of this solve are discarded, section 5.2.2);
 *           with B_0 fixed, blendshapes (w_d 1, w_t 0.5, w_m 0.25, section 5.2.3 (a)) and
 *           weights (bounded least squares, (b)) in turn.
 * The retargeting term E_t pulls each blendshape toward the template's expression moved onto
 * B_0 by deformation transfer (lib/mesh/deformation_transfer.c); the previous-iteration term
 * E_m toward the rig's current shapes (the model-space rig's in the first round). In vertex
 * positions every vertex's unknowns decouple, so each step is a set of equal-sized dense
 * systems (vertex_least_squares.c). Then the rest of the head follows (whole_head.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "core/clock.h"
#include "core/context.h"
#include "frig/retarget.h"
#include "mesh/deformation_transfer.h"
#include "model/model.h"
#include "retarget/retarget.h"
#include "rig/rig.h"
#include "workspace/photoset.h"

void fr_rt_settings_from_ctx(const frig_ctx *ctx, fr_rt_settings *s) {
    memset(s, 0, sizeof *s);
    s->inner_iterations = fr_param_int(ctx, FRIG_PARAM_RETARGET_INNER_ITERATIONS);
    s->alternations = fr_param_int(ctx, FRIG_PARAM_RETARGET_ALTERNATIONS);
    s->rigid_iterations = fr_param_int(ctx, FRIG_PARAM_RETARGET_RIGID_ITERATIONS);
    s->deform_iterations = fr_param_int(ctx, FRIG_PARAM_RETARGET_DEFORM_ITERATIONS);
    s->w_data = fr_param(ctx, FRIG_PARAM_RETARGET_W_DATA);
    s->w_transfer = fr_param(ctx, FRIG_PARAM_RETARGET_W_TRANSFER);
    s->w_prev_neutral = fr_param(ctx, FRIG_PARAM_RETARGET_W_PREV_NEUTRAL);
    s->w_prev_shapes = fr_param(ctx, FRIG_PARAM_RETARGET_W_PREV_SHAPES);
    s->max_distance = 1e-3 * fr_param(ctx, FRIG_PARAM_RETARGET_MAX_DISTANCE_MM);
    s->cos_max_angle = cos(fr_param(ctx, FRIG_PARAM_RETARGET_MAX_NORMAL_ANGLE) * M_PI / 180);
    s->min_confidence = fr_param(ctx, FRIG_PARAM_RETARGET_MIN_CONFIDENCE);
    s->spacing = 1e-3 * fr_param(ctx, FRIG_PARAM_RETARGET_SPACING_MM);
    s->smooth = 1e-3 * fr_param(ctx, FRIG_PARAM_RETARGET_SMOOTH_MM);
    s->smooth_order = fr_param_int(ctx, FRIG_PARAM_RETARGET_SMOOTH_ORDER);
    s->tangential = fr_param(ctx, FRIG_PARAM_RETARGET_TANGENTIAL);
    s->weights_prior = fr_param(ctx, FRIG_PARAM_RETARGET_WEIGHTS_PRIOR);
    s->weights_sparse = fr_param(ctx, FRIG_PARAM_RETARGET_WEIGHTS_SPARSE);
    s->identity_iterations = fr_param_int(ctx, FRIG_PARAM_RETARGET_IDENTITY_ITERATIONS);
    s->landmark_sigma = 1e-3 * fr_param(ctx, FRIG_PARAM_RETARGET_LANDMARK_MM);
    s->cloud_scale = fr_param_int(ctx, FRIG_PARAM_RETARGET_CLOUD_SCALE);
    s->transfer_gradients = fr_param_int(ctx, FRIG_PARAM_RETARGET_TRANSFER);
    s->anchor_frame = fr_param_int(ctx, FRIG_PARAM_RETARGET_ANCHOR_FRAME);
    s->identity_prior = fr_param(ctx, FRIG_PARAM_RETARGET_IDENTITY_PRIOR);
    s->prior_centre = fr_param(ctx, FRIG_PARAM_RETARGET_IDENTITY_PRIOR_CENTRE);
    s->identity_spread = fr_param(ctx, FRIG_PARAM_RETARGET_IDENTITY_SPREAD);
    s->margin_weight = fr_param(ctx, FRIG_PARAM_RETARGET_MARGIN_WEIGHT);
    s->mean_size = fr_param_int(ctx, FRIG_PARAM_FIT_MEAN_SIZE);
    s->weights_ridge = fr_param(ctx, FRIG_PARAM_RETARGET_IDENTITY_WEIGHTS_RIDGE);
    s->max_correction = fr_param(ctx, FRIG_PARAM_RETARGET_MAX_CORRECTION_DEG) * M_PI / 180;
    s->max_rms = 1e-3 * fr_param(ctx, FRIG_PARAM_RETARGET_MAX_RMS_MM);
    s->threads = fr_threads(ctx);
}

/* The working state of one retarget pass on the face. */
typedef struct state {
    const fr_rt_settings *s;
    fr_rt_mesh mesh;
    int nf, S, K;          /* face vertices, rig shapes, fitting shapes */
    int *fit_shape;        /* rig shape of each fitting weight (K) */
    uint8_t *is_fitting;   /* per rig shape */
    float *N;              /* neutral, 3 nf */
    float *D;              /* all rig shapes' deltas on the face, shape j at 3 nf j */
    float *Dfit;           /* the fitting shapes' deltas, weight order, 3 nf K */
    float *A0, *Ad;        /* template neutral and deltas (per rig shape) on the face */
    float *T;              /* transferred template deltas, per rig shape */
    int n;
    fr_rt_photo *photos;
    fr_lap_system *lap;
    fr_lap_solver **solvers; /* one per thread */
    fr_tri_tree **trees;     /* one per thread */
} state;

static size_t face3(const state *st) { return 3 * (size_t)st->nf; }

static void gather_fitting(state *st) {
    size_t n3 = face3(st);
    for (int a = 0; a < st->K; a++) memcpy(st->Dfit + n3 * a, st->D + n3 * st->fit_shape[a], sizeof(float) * n3);
}

/* B (x) w_i on the face. */
static void reconstruction(const state *st, const double *w, float *out) {
    fr_rt_blend(face3(st), st->N, st->K, w, st->Dfit, face3(st), NULL, out);
}

static frig_status correspond_all(frig_ctx *ctx, state *st) {
    size_t n3 = face3(st);
    /* The smoothness of the displacements is measured on the current neutral. */
    frig_status rs = fr_lap_system_set_rest(ctx, st->lap, st->N);
    if (rs) return rs;
    int threads = st->s->threads, failed = 0;
    float *rest = malloc(sizeof(float) * n3 * (size_t)threads);
    if (!rest) return fr_nomem(ctx, "the correspondences");
    atomic_size_t done;
    atomic_init(&done, 0);
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (int i = 0; i < st->n; i++) {
        if (failed || fr_cancelled(ctx)) continue;
        int tid = omp_get_thread_num();
        float *r = rest + n3 * (size_t)tid;
        reconstruction(st, st->photos[i].w, r);
        if (fr_rt_correspond(ctx, st->s, &st->mesh, st->solvers[tid], fr_lap_system_mass(st->lap), st->trees[tid], r,
                             &st->photos[i]))
            failed = 1;
        fr_progress_tick(ctx, &done, "retarget.correspond", (size_t)st->n);
    }
    fr_blas_serial_end(saved);
    free(rest);
    if (failed) return ctx->status ? ctx->status : FRIG_ERR_INTERNAL;
    return fr_check_cancel(ctx, "retarget");
}

/* T_j = the template's expression j moved onto the current neutral by deformation transfer, the
 * rim held at the template's own deltas (retarget.transfer 1); or the template's deltas
 * themselves (0). */
static frig_status transfer_template(frig_ctx *ctx, state *st) {
    if (!st->s->transfer_gradients) {
        /* The template's deltas as they are, vertex by vertex. */
        memcpy(st->T, st->Ad, sizeof(float) * face3(st) * (size_t)st->S);
        return FRIG_OK;
    }
    fr_dtransfer *dt = NULL;
    frig_status s = fr_dtransfer_create(ctx, st->nf, st->mesh.tris, st->mesh.nt, st->A0, st->N, st->mesh.rim, &dt);
    if (!s) s = fr_dtransfer_apply(ctx, dt, st->S, st->Ad, NULL, st->T);
    fr_dtransfer_free(dt);
    return s;
}

static frig_status with_coverage(frig_ctx *ctx, const state *st, const float ***cover, const float ***targets) {
    *cover = malloc(sizeof(float *) * ((size_t)st->n + 1));
    *targets = malloc(sizeof(float *) * ((size_t)st->n + 1));
    if (!*cover || !*targets) return fr_nomem(ctx, "the retarget systems");
    for (int i = 0; i < st->n; i++) (*cover)[i] = st->photos[i].cover, (*targets)[i] = st->photos[i].M;
    return FRIG_OK;
}

/* Section 5.2.2: [B_0, D_1 .. D_K] per vertex from all M'_i; keep B_0. */
static frig_status solve_neutral(frig_ctx *ctx, state *st) {
    const fr_rt_settings *s = st->s;
    int m = st->K + 1, nf = st->nf;
    size_t n3 = face3(st);
    double *A = malloc(sizeof(double) * (size_t)m * ((size_t)st->n + 1)), *reg = malloc(sizeof(double) * m);
    double *prior = malloc(sizeof(double) * (size_t)nf * m * 3), *X = malloc(sizeof(double) * (size_t)nf * m * 3);
    const float **cover = NULL, **targets = NULL;
    frig_status r = A && reg && prior && X ? with_coverage(ctx, st, &cover, &targets) : fr_nomem(ctx, "the neutral");
    if (!r) {
        for (int i = 0; i < st->n; i++) {
            A[(size_t)m * i] = 1;
            for (int a = 0; a < st->K; a++) A[(size_t)m * i + 1 + a] = st->photos[i].w[a];
        }
        reg[0] = s->w_prev_neutral / s->w_data;
        for (int a = 0; a < st->K; a++) reg[1 + a] = s->w_transfer / s->w_data;
        for (int v = 0; v < nf; v++)
            for (int k = 0; k < 3; k++) {
                double *pv = prior + (size_t)v * m * 3 + (size_t)k * m;
                pv[0] = reg[0] * st->N[3 * (size_t)v + k];
                for (int a = 0; a < st->K; a++) pv[1 + a] = reg[1 + a] * st->T[n3 * st->fit_shape[a] + 3 * (size_t)v + k];
            }
        r = fr_rt_vertex_solve(ctx, s->threads, nf, st->n, m, A, cover, targets, NULL, reg, prior, X);
    }
    if (!r)
        for (int v = 0; v < nf; v++)
            for (int k = 0; k < 3; k++) st->N[3 * (size_t)v + k] = (float)X[(size_t)v * m * 3 + (size_t)k * m];
    free(A), free(reg), free(prior), free(X), free(cover), free(targets);
    return r;
}

/* Section 5.2.3 (a): the fitting shapes with B_0 fixed. */
static frig_status solve_shapes(frig_ctx *ctx, state *st, const float *D_prev) {
    const fr_rt_settings *s = st->s;
    int m = st->K, nf = st->nf;
    size_t n3 = face3(st);
    double *A = malloc(sizeof(double) * (size_t)m * ((size_t)st->n + 1)), *reg = malloc(sizeof(double) * (m + 1));
    double *prior = malloc(sizeof(double) * (size_t)nf * m * 3), *X = malloc(sizeof(double) * (size_t)nf * m * 3);
    const float **cover = NULL, **targets = NULL;
    frig_status r = A && reg && prior && X ? with_coverage(ctx, st, &cover, &targets) : fr_nomem(ctx, "the blendshapes");
    if (!r) {
        for (int i = 0; i < st->n; i++) memcpy(A + (size_t)m * i, st->photos[i].w, sizeof(double) * m);
        double wt = s->w_transfer / s->w_data, wm = s->w_prev_shapes / s->w_data;
        for (int a = 0; a < m; a++) reg[a] = wt + wm;
        for (int v = 0; v < nf; v++)
            for (int k = 0; k < 3; k++) {
                double *pv = prior + (size_t)v * m * 3 + (size_t)k * m;
                for (int a = 0; a < m; a++) {
                    size_t q = n3 * st->fit_shape[a] + 3 * (size_t)v + k;
                    pv[a] = wt * st->T[q] + wm * D_prev[q];
                }
            }
        r = fr_rt_vertex_solve(ctx, s->threads, nf, st->n, m, A, cover, targets, st->N, reg, prior, X);
    }
    if (!r)
        for (int a = 0; a < m; a++)
            for (int v = 0; v < nf; v++)
                for (int k = 0; k < 3; k++)
                    st->D[n3 * st->fit_shape[a] + 3 * (size_t)v + k] = (float)X[(size_t)v * m * 3 + (size_t)k * m + a];
    free(A), free(reg), free(prior), free(X), free(cover), free(targets);
    return r;
}

static frig_status setup(frig_ctx *ctx, const fr_rt_settings *s, const frig_model *model, const frig_rig *rig,
                         int nf, state *st) {
    st->s = s;
    st->nf = nf;
    st->S = rig->shape_count;
    size_t n3 = face3(st);
    st->N = malloc(sizeof(float) * n3);
    st->D = malloc(sizeof(float) * n3 * ((size_t)st->S + 1));
    st->A0 = malloc(sizeof(float) * n3);
    st->Ad = malloc(sizeof(float) * n3 * ((size_t)st->S + 1));
    st->T = malloc(sizeof(float) * n3 * ((size_t)st->S + 1));
    st->is_fitting = calloc((size_t)st->S + 1, 1);
    st->solvers = calloc((size_t)s->threads, sizeof(fr_lap_solver *));
    st->trees = calloc((size_t)s->threads, sizeof(fr_tri_tree *));
    if (!st->N || !st->D || !st->A0 || !st->Ad || !st->T || !st->is_fitting || !st->solvers || !st->trees)
        return fr_nomem(ctx, "the retarget stage");
    memcpy(st->N, rig->neutral, sizeof(float) * n3);
    memcpy(st->A0, model->neutral, sizeof(float) * n3);
    size_t rig3 = 3 * (size_t)rig->topo.vertex_count;
    for (int j = 0; j < st->S; j++) {
        memcpy(st->D + n3 * j, rig->deltas + rig3 * j, sizeof(float) * n3);
        /* The template's expression of the same name (the rig's own shape when the model lacks it). */
        int e = frig_model_expression_find(model, rig->shape_names[j]);
        const float *src = e >= 0 ? model->expressions + rig3 * (size_t)e : rig->deltas + rig3 * j;
        memcpy(st->Ad + n3 * j, src, sizeof(float) * n3);
    }
    frig_status r = fr_rt_mesh_make(ctx, nf, rig->topo.triangles, rig->topo.triangle_count, rig->neutral, &st->mesh);
    if (!r) r = fr_lap_system_create(ctx, nf, st->mesh.tris, st->mesh.nt, st->N, s->smooth_order, &st->lap);
    for (int t = 0; t < s->threads && !r; t++) r = fr_lap_solver_create(ctx, st->lap, &st->solvers[t]);
    for (int t = 0; t < s->threads && !r; t++) r = fr_tri_tree_copy(ctx, st->mesh.tree, &st->trees[t]);
    return r;
}

static void teardown(state *st) {
    for (int t = 0; st->solvers && t < st->s->threads; t++) fr_lap_solver_free(st->solvers[t]);
    for (int t = 0; st->trees && t < st->s->threads; t++) fr_tri_tree_free(st->trees[t]);
    free(st->solvers);
    free(st->trees);
    fr_lap_system_free(st->lap);
    fr_rt_mesh_free(&st->mesh);
    free(st->N), free(st->D), free(st->Dfit), free(st->A0), free(st->Ad), free(st->T), free(st->is_fitting);
    free(st->fit_shape);
}

frig_status fr_rt_run(frig_ctx *ctx, const fr_rt_settings *s, const frig_model *model, frig_rig *rig, int nf,
                      int K, const int *fit_shape, int n, fr_rt_photo *photos, double *identity, int n_id) {
    state st;
    memset(&st, 0, sizeof st);
    frig_status r = FRIG_OK;
    fr_rt_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    fr_stopwatch t_id = fr_stopwatch_start();
    /* The rig as the pass found it: the frame to come back to and the collisions' reference. */
    size_t all3 = 3 * (size_t)rig->topo.vertex_count;
    float *start = malloc(sizeof(float) * all3), *start_deltas = malloc(sizeof(float) * all3 * (size_t)rig->shape_count);
    if (!start || !start_deltas) {
        free(start), free(start_deltas);
        return fr_nomem(ctx, "the retarget stage");
    }
    memcpy(start, rig->neutral, sizeof(float) * all3);
    memcpy(start_deltas, rig->deltas, sizeof(float) * all3 * (size_t)rig->shape_count);
    /* The identity from the clouds first (the whole head moves with the modes). */
    if (s->identity_iterations > 0 && n_id > 0) {
        r = fr_rt_mesh_make(ctx, nf, rig->topo.triangles, rig->topo.triangle_count, rig->neutral, &mesh);
        for (int i = 0; i < n && !r; i++) r = fr_rt_thin_cloud(ctx, s, &photos[i]);
        if (!r)
            r = fr_rt_fit_identity(ctx, s, model, rig, &mesh, K, fit_shape, n, photos, identity, n_id,
                                   s->identity_iterations);
        fr_rt_mesh_free(&mesh);
    }
    double wall = 0, cpu = 0;
    fr_stopwatch_read(&t_id, &wall, &cpu);
    if (!r) fr_log(ctx, FRIG_LOG_DEBUG, "retarget: identity from the clouds %.2f s (%.2f CPU s)", wall, cpu);
    if (!r) r = setup(ctx, s, model, rig, nf, &st);
    size_t n3 = face3(&st);
    st.K = K;
    st.n = n;
    st.photos = photos;
    st.fit_shape = malloc(sizeof(int) * ((size_t)K + 1));
    st.Dfit = malloc(sizeof(float) * n3 * ((size_t)K + 1));
    float *D_prev = malloc(sizeof(float) * n3 * ((size_t)st.S + 1));
    if (!r && (!st.fit_shape || !st.Dfit || !D_prev)) r = fr_nomem(ctx, "the retarget stage");
    if (!r) {
        memcpy(st.fit_shape, fit_shape, sizeof(int) * (size_t)K);
        for (int a = 0; a < K; a++) st.is_fitting[fit_shape[a]] = 1;
        gather_fitting(&st);
    }
    for (int i = 0; i < n && !r; i++) r = fr_rt_thin_cloud(ctx, s, &photos[i]);
    for (int it = 0; it < s->inner_iterations && !r; it++) {
        memcpy(D_prev, st.D, sizeof(float) * n3 * (size_t)st.S);
        double t[6];
        t[0] = fr_cpu_seconds();
        r = correspond_all(ctx, &st);
        t[1] = fr_cpu_seconds();
        if (!r) r = transfer_template(ctx, &st);
        t[2] = fr_cpu_seconds();
        if (!r) r = solve_neutral(ctx, &st);
        t[3] = fr_cpu_seconds();
        if (!r) r = transfer_template(ctx, &st);
        double t_shapes = 0, t_weights = 0;
        for (int alt = 0; alt < s->alternations && !r; alt++) {
            t[4] = fr_cpu_seconds();
            r = solve_shapes(ctx, &st, D_prev);
            if (!r) gather_fitting(&st);
            t[5] = fr_cpu_seconds();
            if (!r) r = fr_rt_fit_weights(ctx, s, nf, K, st.N, st.Dfit, n, photos);
            t_shapes += t[5] - t[4], t_weights += fr_cpu_seconds() - t[5];
        }
        fr_log(ctx, FRIG_LOG_DEBUG,
               "retarget round %d (CPU s): correspondences %.2f, transfer %.2f, neutral %.2f, shapes %.2f, "
               "weights %.2f", it + 1, t[1] - t[0], t[2] - t[1], t[3] - t[2], t_shapes, t_weights);
        /* Shapes no photo's weights drive (not fitted) are the template's, transferred. */
        for (int j = 0; j < st.S && !r; j++)
            if (!st.is_fitting[j]) memcpy(st.D + n3 * j, st.T + n3 * j, sizeof(float) * n3);
        fr_log(ctx, FRIG_LOG_INFO, "retarget round %d of %d done", it + 1, s->inner_iterations);
    }
    /* Write the face back into the rig; the rest of the head follows. */
    if (!r) {
        size_t rig3 = 3 * (size_t)rig->topo.vertex_count;
        float *old_neutral = malloc(sizeof(float) * rig3), *old_deltas = malloc(sizeof(float) * rig3 * st.S);
        if (!old_neutral || !old_deltas) r = fr_nomem(ctx, "the whole head");
        if (!r) {
            memcpy(old_neutral, rig->neutral, sizeof(float) * rig3);
            memcpy(old_deltas, rig->deltas, sizeof(float) * rig3 * st.S);
            memcpy(rig->neutral, st.N, sizeof(float) * n3);
            for (int j = 0; j < st.S; j++) memcpy(rig->deltas + rig3 * j, st.D + n3 * j, sizeof(float) * n3);
            fr_stopwatch t_head = fr_stopwatch_start();
            r = fr_rt_whole_head(ctx, model, nf, old_neutral, old_deltas, start, start_deltas, rig);
            fr_stopwatch_read(&t_head, &wall, &cpu);
            fr_log(ctx, FRIG_LOG_DEBUG, "retarget: the whole head %.2f s (%.2f CPU s)", wall, cpu);
        }
        if (!r && s->anchor_frame == 2 && n_id > 0) {
            /* the frame of the model at the identity the clouds gave: the identity modes move the head
             * as a whole too, and that part is the identity's (its shape tells it through the modes) */
            float *frame = malloc(sizeof(float) * rig3);
            if (!frame) r = fr_nomem(ctx, "the rig's frame");
            if (!r) r = frig_model_eval(ctx, model, identity, NULL, frame);
            if (!r) fr_rt_anchor_frame(rig, nf, frame);
            free(frame);
        } else if (!r && s->anchor_frame) fr_rt_anchor_frame(rig, nf, start);
        free(old_neutral), free(old_deltas);
    }
    free(start), free(start_deltas);
    free(D_prev);
    teardown(&st);
    return r;
}
