/* The fit stage on synthetic ground truth (frig synth): subjects outside the model's span,
 * landmarks = the truth's detector-like landmarks + noise, some photos corrupted. Checks
 * that the progressive scheme recovers the neutral shape better than the mean face and
 * than individual fits, head poses within a few degrees, sparse expressions; that results do
 * not depend on the thread count; and frig_fit on a photo set (statuses, report round trip). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "eval/shape_error.h"
#include "fit/photo_consistency.h"
#include "fit/photo_fit.h"
#include "fit/progressive_fit.h"
#include "fit/outline_fit.h"
#include "fit/landmark_vertices.h"
#include "frig/synth.h"
#include "model_fixture.h"
#include "raster/rotation.h"
#include "testing.h"
#include "workspace/photoset.h"

#define PHOTOS 16
#define SIZE 320

typedef struct data {
    int n;
    fr_fit_input in[PHOTOS];
    double landmarks[PHOTOS][136];
    double R[PHOTOS][9];
    int truth_active; /* truth expression weights above 0.15, summed over the good photos */
    frig_image *photo[PHOTOS];
    frig_image *crop[PHOTOS];
    const frig_rig *truth;
} data;

static unsigned long long rng_state = 12345;
static double uniform(void) {
    rng_state += 0x9E3779B97F4A7C15ULL;
    unsigned long long z = rng_state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return (double)((z ^ (z >> 31)) >> 11) / 9007199254740992.0;
}
static double gauss(void) { return sqrt(-2 * log(uniform() + 1e-300)) * cos(2 * M_PI * uniform()); }


static int make_data(frig_ctx *ctx, const frig_synth_subject *subj, uint64_t seed, data *d) {
    memset(d, 0, sizeof *d);
    d->truth = frig_synth_subject_rig(subj);
    for (int p = 0; p < PHOTOS; p++) {
        frig_image *img = NULL;
        frig_synth_truth *tr = NULL;
        if (frig_synth_render(ctx, subj, seed + (uint64_t)p, FRIG_SYNTH_FAILURE_NONE, &img, &tr)) return 0;
        const double *q = frig_synth_truth_landmarks(tr, 1);
        double l[2] = {0, 0}, r[2] = {0, 0};
        for (int k = 36; k < 42; k++) l[0] += q[2 * k] / 6, l[1] += q[2 * k + 1] / 6;
        for (int k = 42; k < 48; k++) r[0] += q[2 * k] / 6, r[1] += q[2 * k + 1] / 6;
        double sigma = 0.02 * hypot(l[0] - r[0], l[1] - r[1]);
        for (int k = 0; k < 136; k++) d->landmarks[p][k] = q[k] + sigma * gauss();
        if (p % 7 == 3) /* a failed detection: the mouth drifts by 15% of the face width */
            for (int k = 48; k < 68; k++) d->landmarks[p][2 * k] += 0.15 * (q[32] - q[0]);
        double t[3];
        frig_synth_truth_pose(tr, d->R[p], t);
        const double *tw = frig_synth_truth_expression(tr);
        for (int k = 0; k < frig_rig_shape_count(d->truth) && p % 7 != 3; k++) d->truth_active += tw[k] > 0.15;
        d->in[p].landmarks = d->landmarks[p];
        d->in[p].width = frig_image_width(img);
        d->in[p].height = frig_image_height(img);
        CHECK(fr_face_crop(ctx, img, d->landmarks[p], 160, &d->crop[p], d->in[p].crop_origin, &d->in[p].crop_scale) ==
              FRIG_OK);
        d->in[p].crop = d->crop[p];
        d->photo[p] = img;
        frig_synth_truth_free(tr);
    }
    d->n = PHOTOS;
    return 1;
}

static void free_data(data *d) {
    for (int p = 0; p < d->n; p++) frig_image_free(d->photo[p]), frig_image_free(d->crop[p]);
}

typedef struct score {
    double neutral_mm, rot_deg;
    int active; /* expression weights above 0.15, summed over the good photos */
} score;

static score run(frig_ctx *ctx, const frig_model *m, const fr_fit_model *fm, const fr_fit_settings *st,
                 fr_fit_scheme scheme, data *d, double *out_w) {
    fr_fit_result res[PHOTOS];
    double identity[512];
    for (int i = 0; i < d->n; i++) res[i].w = out_w + (size_t)i * fm->n_cols;
    score s = {0, 0, 0};
    CHECK(fr_fit_run(ctx, fm, st, scheme, d->n, d->in, res, identity) == FRIG_OK);
    int nv = frig_model_vertex_count(m), nface = 9409;
    float *est = malloc(sizeof(float) * 3 * (size_t)nv);
    int active = 0;
    for (int i = 0; i < d->n; i++) {
        frig_model_eval(ctx, m, res[i].w, NULL, est);
        s.neutral_mm += fr_aligned_mean_distance(frig_rig_neutral(d->truth), est, nface) * 1000 / d->n;
        s.rot_deg += fr_rotation_angle_deg(d->R[i], res[i].R) / d->n;
        if (i % 7 != 3) /* not the corrupted photos */
            for (int k = 0; k < fm->n_exp; k++) active += res[i].w[fm->n_id + k] > 0.15;
        if (getenv("FIT_TEST_VERBOSE") && scheme == FR_SCHEME_PROGRESSIVE) {
            for (int k = 0; k < fm->n_exp; k++)
                if (res[i].w[fm->n_id + k] > 0.15)
                    printf(" %s=%.2f", frig_model_expression_name(m, fm->exp_index[k]), res[i].w[fm->n_id + k]);
            printf("\n");
        }
    }
    s.active = active;
    free(est);
    return s;
}

static void test_schemes(frig_ctx *ctx, const frig_model *m) {
    fr_fit_model fm;
    CHECK(fr_fit_model_build(ctx, m, 100, &fm) == FRIG_OK);
    fr_fit_settings st;
    fr_fit_settings_from_ctx(ctx, &st);
    double *w = malloc(sizeof(double) * PHOTOS * (size_t)fm.n_cols);
    double *w2 = malloc(sizeof(double) * PHOTOS * (size_t)fm.n_cols);
    double sum_mean = 0, sum_ind = 0, sum_prog = 0, sum_rot = 0, sum_default = 0;
    for (int subject = 0; subject < 2; subject++) {
        frig_synth_subject *subj = NULL;
        CHECK(frig_synth_subject_create(ctx, m, 4000 + (uint64_t)subject, &subj) == FRIG_OK);
        data d;
        if (!subj || !make_data(ctx, subj, 77000 + 100 * (uint64_t)subject, &d)) {
            test_failures++;
            return;
        }
        int nv = frig_model_vertex_count(m);
        float *mean = malloc(sizeof(float) * 3 * (size_t)nv);
        frig_model_eval(ctx, m, NULL, NULL, mean);
        double mean_mm = fr_aligned_mean_distance(frig_rig_neutral(d.truth), mean, 9409) * 1000;
        free(mean);
        score ind = run(ctx, m, &fm, &st, FR_SCHEME_INDIVIDUAL, &d, w);
        /* The paper's joint prior (the subset's centroid), which is best on these landmarks, and
         * the default (the model mean), which is best on a detector's (docs/fit.md). */
        double default_prior = st.joint_prior;
        st.joint_prior = 1;
        score prog = run(ctx, m, &fm, &st, FR_SCHEME_PROGRESSIVE, &d, w);
        st.joint_prior = default_prior;
        score prog_default = run(ctx, m, &fm, &st, FR_SCHEME_PROGRESSIVE, &d, w2);
        sum_default += prog_default.neutral_mm / 2;
        int good = d.n - (d.n + 3) / 7;
        printf("subject %d: neutral error (mm, aligned, face region): mean face %.2f, individual %.2f, progressive "
               "%.2f; rotation error %.2f deg; expressions above 0.15 per good photo: %.2f (truth %.2f)\n",
               subject, mean_mm, ind.neutral_mm, prog.neutral_mm, prog.rot_deg, (double)prog.active / good,
               (double)d.truth_active / good);
        sum_mean += mean_mm / 2, sum_ind += ind.neutral_mm / 2, sum_prog += prog.neutral_mm / 2;
        sum_rot += prog.rot_deg / 2;
        CHECK(prog.active <= d.truth_active + 2 * good); /* sparse: at most 2 more active shapes than the truth */
        if (subject == 0) {
            /* Threads do not change a bit of the result. */
            st.threads = 1;
            run(ctx, m, &fm, &st, FR_SCHEME_PROGRESSIVE, &d, w2);
            st.threads = 2;
            score again = run(ctx, m, &fm, &st, FR_SCHEME_PROGRESSIVE, &d, w);
            CHECK(memcmp(w, w2, sizeof(double) * PHOTOS * (size_t)fm.n_cols) == 0);
            CHECK(again.neutral_mm == prog_default.neutral_mm);
            st.threads = fr_threads(ctx);
        }
        free_data(&d);
        frig_synth_subject_free(subj);
    }
    printf("average: mean face %.2f mm, individual fits %.2f mm, progressive %.2f mm (default prior %.2f mm), "
           "rotation %.2f deg\n", sum_mean, sum_ind, sum_prog, sum_default, sum_rot);
    CHECK(sum_default < sum_mean);
    CHECK(sum_prog < sum_ind);
    CHECK(sum_prog < 0.92 * sum_mean);
    CHECK(sum_prog < 3.5);
    CHECK(sum_rot < 5.0);
    free(w);
    free(w2);
    fr_fit_model_free(&fm);
}

/* frig_fit over a photo set: photos written as JPEG, landmarks as user landmarks. */
static void test_photoset(frig_ctx *ctx, const frig_model *m) {
    const char *dir = test_temp_dir("fit_photoset");
    frig_synth_subject *subj = NULL;
    CHECK(frig_synth_subject_create(ctx, m, 4100, &subj) == FRIG_OK);
    data d;
    if (!subj || !make_data(ctx, subj, 91000, &d)) {
        test_failures++;
        return;
    }
    frig_photoset *set = NULL;
    frig_photoset_create(ctx, &set);
    CHECK(frig_fit(ctx, m, set) == FRIG_ERR_TOO_FEW);
    for (int p = 0; p < 10; p++) {
        char path[4200];
        snprintf(path, sizeof path, "%s/photo_%02d.jpg", dir, p);
        CHECK(frig_image_save_jpeg(ctx, d.photo[p], path) == FRIG_OK);
        size_t idx, f;
        frig_photoset_add(ctx, set, path, &idx);
        double box[4] = {0, 0, 100, 100};
        frig_photoset_add_face(ctx, set, idx, box, 1, FRIG_FACE_USER, d.landmarks[p], &f);
        frig_photoset_set_subject(ctx, set, idx, 0);
        frig_photoset_set_status(ctx, set, idx, FRIG_PHOTO_OK, NULL);
    }
    /* A photo that vanished since detection, and one without a face: reported, not fitted. */
    size_t gone, noface;
    frig_photoset_add(ctx, set, "/nonexistent/photo.jpg", &gone);
    double box[4] = {0, 0, 100, 100};
    frig_photoset_add_face(ctx, set, gone, box, 1, FRIG_FACE_USER, d.landmarks[0], NULL);
    frig_photoset_set_subject(ctx, set, gone, 0);
    frig_photoset_set_status(ctx, set, gone, FRIG_PHOTO_OK, NULL);
    frig_photoset_add(ctx, set, "/nonexistent/other.jpg", &noface);
    frig_photoset_set_status(ctx, set, noface, FRIG_PHOTO_NO_FACE, "no face");
    CHECK(frig_fit(ctx, m, set) == FRIG_OK);
    CHECK(frig_photoset_status(set, gone) == FRIG_PHOTO_UNREADABLE);
    CHECK(!frig_photoset_fitted(set, noface));
    int fitted = 0, joint = 0;
    for (size_t i = 0; i < 10; i++) {
        fitted += frig_photoset_fitted(set, i);
        joint += frig_photoset_fit_in_joint(set, i);
        CHECK(frig_photoset_fit_error(set, i) < 15);
    }
    CHECK(fitted == 10 && joint == 8); /* the last round's joint subset is 0.8 of the photos */
    const double *id;
    CHECK(frig_photoset_identity(set, &id) == 100);
    CHECK(frig_photoset_fit_expression_count(set) == 53);
    /* The report keeps every fitted number exactly. */
    char ws[4200];
    snprintf(ws, sizeof ws, "%s/ws", dir);
    CHECK(frig_photoset_save(ctx, set, ws) == FRIG_OK);
    frig_photoset *back = NULL;
    CHECK(frig_photoset_load(ctx, ws, &back) == FRIG_OK);
    if (back) {
        const double *id2;
        CHECK(frig_photoset_identity(back, &id2) == 100 && memcmp(id, id2, sizeof(double) * 100) == 0);
        double R1[9], R2[9], t1[3], t2[3], w1[53], w2[53];
        CHECK(frig_photoset_fit_pose(set, 3, R1, t1, NULL, NULL) == FRIG_OK);
        CHECK(frig_photoset_fit_pose(back, 3, R2, t2, NULL, NULL) == FRIG_OK);
        CHECK(memcmp(R1, R2, sizeof R1) == 0 && memcmp(t1, t2, sizeof t1) == 0);
        CHECK(frig_photoset_fit_expression(set, 3, w1) == FRIG_OK && frig_photoset_fit_expression(back, 3, w2) == FRIG_OK);
        CHECK(memcmp(w1, w2, sizeof w1) == 0);
        CHECK(strcmp(frig_photoset_fit_expression_name(back, 0), frig_photoset_fit_expression_name(set, 0)) == 0);
    }
    /* Overlays for every fitted photo. */
    char ov[4200];
    snprintf(ov, sizeof ov, "%s/overlays", dir);
    CHECK(frig_fit_write_overlays(ctx, m, set, ov) == FRIG_OK);
    snprintf(ov, sizeof ov, "%s/overlays/photo_05.jpg", dir);
    CHECK(test_file_exists(ov));
    frig_photoset_free(back);
    frig_photoset_free(set);
    free_data(&d);
    frig_synth_subject_free(subj);
}

/* The mean rotation error of the fitted poses after the turn of the head frame common to all
 * photos (R_fit = R_true Q: the identity's frame, which the photos cannot see), and that turn. */
static double relative_rotation_error(double Rtrue[][9], const fr_fit_result *res, int n, double *turn_deg) {
    double wm[3] = {0, 0, 0}, Q[9], e = 0;
    for (int i = 0; i < n; i++) {
        double Rt[9], D[9], w[3];
        fr_mat3_transpose(Rtrue[i], Rt);
        fr_mat3_mul(Rt, res[i].R, D);
        fr_rotation_to_axis_angle(D, w);
        for (int q = 0; q < 3; q++) wm[q] += w[q] / n;
    }
    fr_rotation_from_axis_angle(wm, Q);
    for (int i = 0; i < n; i++) {
        double RQ[9];
        fr_mat3_mul(Rtrue[i], Q, RQ);
        e += fr_rotation_angle_deg(res[i].R, RQ) / n;
    }
    *turn_deg = 57.29578 * sqrt(wm[0] * wm[0] + wm[1] * wm[1] + wm[2] * wm[2]);
    return e;
}

/* The outline tests' scene: the model for fitting, synth subject 4200 and its 16 photos (seed
 * 92000). Returns 0 (a failure counted) when it cannot be made. */
static int outline_scene(frig_ctx *ctx, const frig_model *m, fr_fit_model *fm, frig_synth_subject **subj, data *d) {
    CHECK(fr_fit_model_build(ctx, m, 100, fm) == FRIG_OK);
    CHECK(frig_synth_subject_create(ctx, m, 4200, subj) == FRIG_OK);
    if (!*subj || !make_data(ctx, *subj, 92000, d)) {
        test_failures++;
        return 0;
    }
    return 1;
}

/* The outline steps (outline_fit.c) after the progressive fit: the outlines come nearer the
 * photos' edges and the neutral nearer the truth, the same bytes at 1 and 2 threads. */
static void test_outline(frig_ctx *ctx, const frig_model *m) {
    const char *dir = test_temp_dir("fit_outline");
    fr_fit_model fm;
    frig_synth_subject *subj = NULL;
    data d;
    if (!outline_scene(ctx, m, &fm, &subj, &d)) return;
    char paths[PHOTOS][4200];
    const char *pp[PHOTOS];
    for (int p = 0; p < PHOTOS; p++) {
        snprintf(paths[p], sizeof paths[p], "%s/photo_%02d.png", dir, p);
        CHECK(frig_image_save_png(ctx, d.photo[p], paths[p]) == FRIG_OK);
        pp[p] = paths[p];
    }
    fr_fit_settings st;
    fr_fit_settings_from_ctx(ctx, &st);
    double *w = calloc((size_t)PHOTOS * fm.n_cols * 3, sizeof(double)), id[3][128];
    fr_fit_result res[3][PHOTOS];
    for (int i = 0; i < PHOTOS; i++) res[0][i].w = w + (size_t)i * fm.n_cols;
    CHECK(fr_fit_run(ctx, &fm, &st, FR_SCHEME_PROGRESSIVE, d.n, d.in, res[0], id[0]) == FRIG_OK);
    double err[3], moved[2] = {0, 0};
    int nv = frig_model_vertex_count(m);
    float *est = malloc(sizeof(float) * 3 * (size_t)nv);
    for (int k = 1; k < 3; k++) {
        memcpy(id[k], id[0], sizeof id[0]);
        for (int i = 0; i < PHOTOS; i++) {
            res[k][i] = res[0][i];
            res[k][i].w = w + (size_t)(k * PHOTOS + i) * fm.n_cols;
            memcpy(res[k][i].w, res[0][i].w, sizeof(double) * fm.n_cols);
        }
        fr_outline_options o = {16, 30, 0, k, 1};
        CHECK(fr_fit_outline(ctx, &fm, &o, d.n, pp, d.in, res[k], id[k], k == 1 ? moved : NULL) == FRIG_OK);
    }
    for (int k = 0; k < 3; k++) {
        frig_model_eval(ctx, m, id[k], NULL, est);
        err[k] = 1e3 * fr_aligned_mean_distance(frig_rig_neutral(d.truth), est, 9409);
    }
    double rot[2], turn[2];
    for (int k = 0; k < 2; k++) rot[k] = relative_rotation_error(d.R, res[k], PHOTOS, &turn[k]);
    printf("outline steps: the outlines %.2f -> %.2f px from the photos' edges, neutral %.3f -> %.3f mm, rotation "
           "error after the photos' common turn %.2f -> %.2f deg (the turn %.2f -> %.2f deg)\n",
           moved[0], moved[1], err[0], err[1], rot[0], rot[1], turn[0], turn[1]);
    /* measured at the defaults (16 steps, prior 30, the size free): 1.29 -> 0.75 px, 3.845 -> 2.892 mm
     * (subject 4200, 16 photos of 320 px) */
    CHECK(moved[1] < 0.8 * moved[0]);
    CHECK(err[1] < err[0] - 0.1);
    CHECK(rot[1] < rot[0] + 1.0); /* 1.95 -> 2.10: with nearly exact landmarks (2% of the eye distance) the outlines cost the poses a little */
    CHECK(memcmp(id[1], id[2], sizeof(double) * fm.n_id) == 0);
    for (int i = 0; i < PHOTOS; i++) CHECK(memcmp(res[1][i].R, res[2][i].R, sizeof res[1][i].R) == 0);
    free(est), free(w);
    free_data(&d);
    frig_synth_subject_free(subj);
    fr_fit_model_free(&fm);
}

/* The face's scale that the residual unit and the fit_failed test use: the eye distance on a
 * frontal face, half the landmarks' height on a turned one whose eyes close up. */
static void test_face_scale(void) {
    double q[136];
    for (int k = 0; k < 68; k++) q[2 * k] = 100, q[2 * k + 1] = 100 + k; /* 67 px tall */
    for (int k = 36; k < 42; k++) q[2 * k] = 60;  /* right eye centre x 60 */
    for (int k = 42; k < 48; k++) q[2 * k] = 140; /* left eye centre x 140, at the same mean height as the right */
    for (int k = 36; k < 42; k++) q[2 * k + 1] = q[2 * (k + 6) + 1] = 130;
    CHECK_NEAR(fr_fit_eye_distance(q), 80, 1e-9);
    CHECK_NEAR(fr_fit_face_scale(q), 80, 1e-9);
    for (int k = 36; k < 42; k++) q[2 * k] = 95;  /* turned: the eyes 10 px apart */
    for (int k = 42; k < 48; k++) q[2 * k] = 105;
    CHECK_NEAR(fr_fit_face_scale(q), 33.5, 1e-9);
}

/* Hair over the forehead and temples, as in photos where it frames the face: above the brows, the head's pixels within 2 pixels of its outline and the background within
 * 12 pixels of the head painted dark brown, so that the photo's edge there lies inside the head's
 * outline. */
static void paint_hair(frig_image *img, const uint8_t *mask, const double *lm) {
    int w = frig_image_width(img), h = frig_image_height(img), c = frig_image_channels(img);
    size_t stride = frig_image_stride(img);
    uint8_t *px = frig_image_pixels_mutable(img);
    double brows = lm[2 * 17 + 1];
    for (int k = 18; k < 27; k++) brows = fmin(brows, lm[2 * k + 1]);
    for (int y = 0; y < h && y < brows; y++)
        for (int x = 0; x < w; x++) {
            int head = mask[(size_t)y * w + x] & FRIG_SYNTH_PIXEL_HEAD, r = head ? 3 : 12, near = 0;
            for (int v = y - r; v <= y + r && !near; v++)
                for (int u = x - r; u <= x + r && !near; u++)
                    if (u >= 0 && v >= 0 && u < w && v < h)
                        near = (mask[(size_t)v * w + u] & FRIG_SYNTH_PIXEL_HEAD) != head;
            if (!near) continue;
            uint8_t *q = px + (size_t)y * stride + (size_t)x * c;
            unsigned t = (unsigned)((x * 7 + y * 13) % 17); /* strands */
            q[0] = (uint8_t)(50 + t), q[1] = (uint8_t)(34 + t), q[2] = (uint8_t)(24 + t / 2);
        }
}

static double rms_size(const float *xyz) {
    double c[3] = {0, 0, 0}, s = 0;
    for (int i = 0; i < 9409; i++)
        for (int k = 0; k < 3; k++) c[k] += xyz[3 * i + k] / 9409;
    for (int i = 0; i < 9409; i++)
        for (int k = 0; k < 3; k++) s += (xyz[3 * i + k] - c[k]) * (xyz[3 * i + k] - c[k]);
    return sqrt(s / 9409);
}

/* The outline steps with the face's size free, on photos with and without hair above the brows:
 * with the band (fit.outline_band 1) the fitted face is the same or better; with the whole face
 * region's outline (0) the hair's edges move it away from the truth (the subject's skin is dark,
 * like the hair, so the skin test of the edges' inner side does not stop them). */
static void test_outline_hair(frig_ctx *ctx, const frig_model *m) {
    const char *dir = test_temp_dir("fit_outline_hair");
    fr_fit_model fm;
    frig_synth_subject *subj = NULL;
    data d;
    if (!outline_scene(ctx, m, &fm, &subj, &d)) return;
    char paths[2][PHOTOS][4200];
    const char *pp[2][PHOTOS];
    for (int p = 0; p < PHOTOS; p++) {
        frig_image *hair = NULL;
        frig_synth_truth *tr = NULL;
        int mw = 0, mh = 0;
        CHECK(frig_synth_render(ctx, subj, 92000 + (uint64_t)p, FRIG_SYNTH_FAILURE_NONE, &hair, &tr) == FRIG_OK);
        const uint8_t *mask = tr ? frig_synth_truth_mask(tr, &mw, &mh) : NULL;
        if (hair && mask && mw == frig_image_width(hair) && mh == frig_image_height(hair))
            paint_hair(hair, mask, frig_synth_truth_landmarks(tr, 0));
        else
            test_failures++;
        frig_synth_truth_free(tr);
        for (int k = 0; k < 2; k++) {
            snprintf(paths[k][p], sizeof paths[k][p], "%s/%s_%02d.png", dir, k ? "hair" : "clean", p);
            CHECK(frig_image_save_png(ctx, k && hair ? hair : d.photo[p], paths[k][p]) == FRIG_OK);
            pp[k][p] = paths[k][p];
        }
        frig_image_free(hair);
    }
    fr_fit_settings st;
    fr_fit_settings_from_ctx(ctx, &st);
    st.mean_size = 0;
    double *w = calloc((size_t)PHOTOS * fm.n_cols * 2, sizeof(double)), id0[128], id[128];
    fr_fit_result res0[PHOTOS], res[PHOTOS];
    for (int i = 0; i < PHOTOS; i++) res0[i].w = w + (size_t)i * fm.n_cols, res[i].w = w + (size_t)(PHOTOS + i) * fm.n_cols;
    CHECK(fr_fit_run(ctx, &fm, &st, FR_SCHEME_PROGRESSIVE, d.n, d.in, res0, id0) == FRIG_OK);
    int nv = frig_model_vertex_count(m);
    float *est = malloc(sizeof(float) * 3 * (size_t)nv);
    double size[2][2], err[2][2]; /* [band][hair] */
    for (int band = 0; band < 2; band++)
        for (int hair = 0; hair < 2; hair++) {
            memcpy(id, id0, sizeof id);
            for (int i = 0; i < PHOTOS; i++) {
                double *wi = res[i].w;
                res[i] = res0[i], res[i].w = wi;
                memcpy(wi, res0[i].w, sizeof(double) * fm.n_cols);
            }
            fr_outline_options o = {16, 30, 0, 2, band};
            CHECK(fr_fit_outline(ctx, &fm, &o, d.n, pp[hair], d.in, res, id, NULL) == FRIG_OK);
            frig_model_eval(ctx, m, id, NULL, est);
            size[band][hair] = rms_size(est) / rms_size(frig_rig_neutral(d.truth));
            err[band][hair] = 1e3 * fr_aligned_mean_distance(frig_rig_neutral(d.truth), est, 9409);
        }
    printf("outline steps, size free, fitted face / true face and neutral (mm): the whole face region %.4f, %.3f "
           "clean, %.4f, %.3f with hair; the band %.4f, %.3f clean, %.4f, %.3f with hair\n",
           size[0][0], err[0][0], size[0][1], err[0][1], size[1][0], err[1][0], size[1][1], err[1][1]);
    /* measured (subject 4200, 16 photos of 320 px): the whole region 0.9757, 2.735 mm clean and 0.9794, 2.984 mm
     * with hair; the band 0.9701, 2.891 mm clean and 0.9697, 2.836 mm with hair (on clean renders the forehead's
     * outline helps; in photos with hair it is the hair's) */
    CHECK(err[1][1] < err[1][0] + 0.05);
    CHECK(fabs(size[1][1] / size[1][0] - 1) < 0.005);
    CHECK(err[0][1] > err[0][0] + 0.15);
    free(est), free(w);
    free_data(&d);
    frig_synth_subject_free(subj);
    fr_fit_model_free(&fm);
}

/* The fit's landmark vertices (fit/landmark_vertices.c): with fit.landmark_vertices 1, on
 * ICT-FaceKit's model the nostrils (31-35) and the mouth (48-67) are moved, each by less than
 * 10 mm on the mean face, and the rest are the model's own; 0 (the default) gives the model's
 * own throughout. */
static void test_landmark_vertices(frig_ctx *ctx, const frig_model *m) {
    const int32_t *own = frig_model_landmarks(m);
    const float *mean = frig_model_neutral(m);
    int32_t lv[68];
    CHECK(frig_ctx_get_param(ctx, FRIG_PARAM_FIT_LANDMARK_VERTICES) == 0);
    frig_ctx_set_param(ctx, FRIG_PARAM_FIT_LANDMARK_VERTICES, 1);
    fr_fit_landmark_vertices(ctx, m, lv);
    int moved = 0;
    double farthest = 0;
    for (int k = 0; k < 68; k++) {
        int may_move = (k >= 31 && k <= 35) || k >= 48;
        if (lv[k] == own[k]) continue;
        CHECK(may_move);
        moved++;
        double d2 = 0;
        for (int a = 0; a < 3; a++)
            d2 += (mean[3 * lv[k] + a] - mean[3 * own[k] + a]) * (mean[3 * lv[k] + a] - mean[3 * own[k] + a]);
        farthest = fmax(farthest, 1e3 * sqrt(d2));
    }
    CHECK(moved >= 20);
    CHECK(farthest > 1.0 && farthest < 10.0);
    frig_ctx_set_param(ctx, FRIG_PARAM_FIT_LANDMARK_VERTICES, 0);
    fr_fit_landmark_vertices(ctx, m, lv);
    CHECK(memcmp(lv, own, sizeof lv) == 0);
}

int main(void) {
    test_face_scale();
    frig_ctx *ctx = frig_ctx_create();
    frig_model *m = fixture_model(ctx);
    if (!m) return test_skip("the ICT-FaceKit model (../shared/ict-facekit) is not available");
    frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_IMAGE_SIZE, SIZE);
    frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_MAX_YAW, 50);
    test_landmark_vertices(ctx, m);
    test_schemes(ctx, m);
    test_photoset(ctx, m);
    test_outline(ctx, m);
    test_outline_hair(ctx, m);
    frig_model_free(m);
    frig_ctx_free(ctx);
    return test_result("test_fit");
}
