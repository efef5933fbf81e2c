/* The fit stage's view of the face model (paper section 4.3, eq. 4.2 and 4.4): the rows of
 * the identity and expression bases for the landmark vertices, the jawline contour
 * candidates and the cheek/jaw band whose silhouette turned faces' jaw landmarks follow. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "core/context.h"
#include "model/face_size.h"
#include "fit/fit_model.h"
#include "fit/landmark_vertices.h"

/* The silhouette band: narrow-face vertices between the chin and the eyes, away from the
 * nose (metres, model space: y up, face looking along +z). */
#define BAND_MIN_ABS_X 0.025
#define BAND_Y_BELOW_CHIN 0.010
#define BAND_Y_ABOVE_EYES 0.005

typedef struct slot_map {
    int *of_vertex; /* -1 or slot */
    int *vertex;
    int count, capacity;
} slot_map;

static int slot_add(slot_map *m, int v) {
    if (m->of_vertex[v] >= 0) return m->of_vertex[v];
    if (m->count == m->capacity) {
        int cap = m->capacity ? 2 * m->capacity : 256;
        int *nv = realloc(m->vertex, sizeof(int) * (size_t)cap);
        if (!nv) return -1;
        m->vertex = nv;
        m->capacity = cap;
    }
    m->vertex[m->count] = v;
    m->of_vertex[v] = m->count;
    return m->count++;
}

/* Vertices of the silhouette band, chosen on the neutral. */
#define BAND_EYE_CLEARANCE 0.02 /* keep 2 cm from the eye centres: the sockets fold inward */

typedef struct band {
    double chin_y, eye_y;
    double eye[2][2]; /* x, y of the two eye centres */
} band;

static int in_band(const float *neutral, int v, const band *b) {
    double x = neutral[3 * v], y = neutral[3 * v + 1];
    for (int e = 0; e < 2; e++)
        if (hypot(x - b->eye[e][0], y - b->eye[e][1]) < BAND_EYE_CLEARANCE) return 0;
    return fabs(x) > BAND_MIN_ABS_X && y > b->chin_y - BAND_Y_BELOW_CHIN && y < b->eye_y + BAND_Y_ABOVE_EYES;
}

/* Column k of the basis: an identity mode, then the fitting expressions (the model's, or the
 * rig's shape of the same name: NULL when the rig lacks it). */
static const float *basis_column(const fr_fit_model *fm, int k) {
    const frig_model *m = fm->model;
    size_t n3 = 3 * (size_t)frig_model_vertex_count(m);
    if (k < fm->n_id) return frig_model_identity_modes(m) + n3 * (size_t)k;
    int e = fm->exp_index[k - fm->n_id];
    if (!fm->rig) return frig_model_expression_deltas(m) + n3 * (size_t)e;
    return frig_rig_shape_deltas(fm->rig, frig_rig_shape_find(fm->rig, frig_model_expression_name(m, e)));
}

static frig_status gather_basis(frig_ctx *ctx, fr_fit_model *fm) {
    const frig_model *m = fm->model;
    const float *neutral = fm->rig ? frig_rig_neutral(fm->rig) : frig_model_neutral(m);
    size_t rows = 3 * (size_t)fm->n_slots;
    fm->mean = malloc(sizeof(double) * rows);
    fm->basis = malloc(sizeof(double) * rows * (size_t)fm->n_cols);
    if (!fm->mean || !fm->basis) return fr_nomem(ctx, "the fit basis");
    for (int s = 0; s < fm->n_slots; s++)
        for (int c = 0; c < 3; c++) fm->mean[3 * s + c] = neutral[3 * (size_t)fm->slot_vertex[s] + c];
    for (int k = 0; k < fm->n_cols; k++) {
        const float *col = basis_column(fm, k);
        for (int s = 0; s < fm->n_slots; s++)
            for (int c = 0; c < 3; c++)
                fm->basis[(3 * (size_t)s + c) * (size_t)fm->n_cols + k] =
                    col ? col[3 * (size_t)fm->slot_vertex[s] + c] : 0.0;
    }
    return FRIG_OK;
}

/* Angle of a vertex around the face centre (the nose tip's height on the mid-line), in the
 * model's x-y plane, measured so that both sides run 0 (up) .. pi (down) toward the chin. */
static double row_angle(const float *neutral, int v, double centre_y) {
    return atan2(fabs(neutral[3 * (size_t)v]), neutral[3 * (size_t)v + 1] - centre_y);
}

/* The row of a candidate: the jaw landmark on its side with the nearest angle, when the
 * candidate lies within that landmark's sector (halfway to its neighbours; the end sectors
 * extend as far as the neighbouring gap). -1 when it belongs to the chin or no sector. */
static int row_of(const double *angle_of_landmark, int side, double a) {
    int first = side == 0 ? 0 : 9, last = side == 0 ? 7 : 16;
    int best = -1;
    double best_d = 1e300;
    for (int k = first; k <= last; k++) {
        double d = fabs(a - angle_of_landmark[k]);
        if (d < best_d) best_d = d, best = k;
    }
    double chin_d = fabs(a - angle_of_landmark[8]);
    if (chin_d < best_d) return -1;
    /* Gap to the neighbour on the far side of 'best' bounds the end sectors. */
    int nb = side == 0 ? (best == first ? first + 1 : best - 1) : (best == last ? last - 1 : best + 1);
    if (best_d > fabs(angle_of_landmark[nb] - angle_of_landmark[best])) return -1;
    return best;
}

static frig_status build_rows(frig_ctx *ctx, fr_fit_model *fm, slot_map *map, const int32_t *lm,
                              const float *neutral, int band_first, int band_count, const band *bd) {
    double centre_y = neutral[3 * (size_t)lm[30] + 1];
    double angle[FR_CONTOUR_LANDMARKS];
    for (int k = 0; k < FR_CONTOUR_LANDMARKS; k++) angle[k] = row_angle(neutral, lm[k], centre_y);
    /* Candidates: both jawline lists and the cheek band, each once. */
    int cap = band_count + 64, n = 0;
    int *cand = malloc(sizeof(int) * (size_t)cap), *row = malloc(sizeof(int) * (size_t)cap);
    char *seen = calloc((size_t)frig_model_vertex_count(fm->model), 1);
    if (!cand || !row || !seen) {
        free(cand), free(row), free(seen);
        return fr_nomem(ctx, "the fit model");
    }
    for (int side = 0; side < 2; side++) {
        const int32_t *jaw;
        int nj = frig_model_contour(fm->model, side, &jaw);
        for (int k = 0; k < nj && n < cap; k++)
            if (!seen[jaw[k]]) seen[jaw[k]] = 1, cand[n++] = jaw[k];
    }
    for (int v = band_first; v < band_first + band_count && n < cap; v++)
        if (!seen[v] && in_band(neutral, v, bd)) seen[v] = 1, cand[n++] = v;
    for (int k = 0; k <= FR_CONTOUR_LANDMARKS; k++) fm->row_start[k] = 0;
    for (int i = 0; i < n; i++) {
        int side = neutral[3 * (size_t)cand[i]] * fm->side0_sign > 0 ? 0 : 1;
        row[i] = row_of(angle, side, row_angle(neutral, cand[i], centre_y));
        if (row[i] >= 0) fm->row_start[row[i] + 1]++;
    }
    for (int k = 0; k < FR_CONTOUR_LANDMARKS; k++) fm->row_start[k + 1] += fm->row_start[k];
    fm->row_slots = malloc(sizeof(int) * (size_t)(fm->row_start[FR_CONTOUR_LANDMARKS] + 1));
    fm->row_radius = malloc(sizeof(double) * (size_t)(fm->row_start[FR_CONTOUR_LANDMARKS] + 1));
    for (int k = 0; k < FR_CONTOUR_LANDMARKS; k++)
        fm->jaw_radius[k] = hypot(neutral[3 * (size_t)lm[k]], neutral[3 * (size_t)lm[k] + 1] - centre_y);
    int fill[FR_CONTOUR_LANDMARKS];
    memcpy(fill, fm->row_start, sizeof fill);
    frig_status s = fm->row_slots && fm->row_radius ? FRIG_OK : fr_nomem(ctx, "the fit model");
    for (int i = 0; i < n && !s; i++) {
        if (row[i] < 0) continue;
        int sl = slot_add(map, cand[i]);
        if (sl < 0) {
            s = fr_nomem(ctx, "the fit model");
            break;
        }
        fm->row_radius[fill[row[i]]] = hypot(neutral[3 * (size_t)cand[i]], neutral[3 * (size_t)cand[i] + 1] - centre_y);
        fm->row_slots[fill[row[i]]++] = sl;
    }
    free(cand), free(row), free(seen);
    return s;
}

/* Slot neighbours along the edges of the slot triangles (duplicates kept: they only weigh
 * an edge twice in the normal smoothing). */
static frig_status build_adjacency(frig_ctx *ctx, fr_fit_model *fm) {
    fm->adj_start = calloc((size_t)fm->n_slots + 1, sizeof(int));
    fm->adj = malloc(sizeof(int) * 6 * (size_t)(fm->n_tris + 1));
    if (!fm->adj_start || !fm->adj) return fr_nomem(ctx, "the fit model");
    for (int t = 0; t < fm->n_tris; t++)
        for (int c = 0; c < 3; c++) fm->adj_start[fm->tris[3 * t + c] + 1] += 2;
    for (int s = 0; s < fm->n_slots; s++) fm->adj_start[s + 1] += fm->adj_start[s];
    int *fill = malloc(sizeof(int) * (size_t)(fm->n_slots + 1));
    if (!fill) return fr_nomem(ctx, "the fit model");
    memcpy(fill, fm->adj_start, sizeof(int) * (size_t)fm->n_slots);
    for (int t = 0; t < fm->n_tris; t++)
        for (int c = 0; c < 3; c++) {
            int a = fm->tris[3 * t + c];
            fm->adj[fill[a]++] = fm->tris[3 * t + (c + 1) % 3];
            fm->adj[fill[a]++] = fm->tris[3 * t + (c + 2) % 3];
        }
    free(fill);
    return FRIG_OK;
}

frig_status fr_fit_model_build(frig_ctx *ctx, const frig_model *model, int n_id, fr_fit_model *fm) {
    memset(fm, 0, sizeof *fm);
    fm->model = model;
    int nv = frig_model_vertex_count(model);
    int n_model_id = frig_model_identity_count(model);
    fm->n_id = n_id < 0 ? 0 : n_id > n_model_id ? n_model_id : n_id;
    int n_model_exp = frig_model_expression_count(model);
    fm->exp_index = malloc(sizeof(int) * (size_t)(n_model_exp > 0 ? n_model_exp : 1));
    if (!fm->exp_index) return fr_nomem(ctx, "the fit model");
    for (int k = 0; k < n_model_exp; k++)
        if (frig_model_expression_fitting(model, k)) fm->exp_index[fm->n_exp++] = k;
    fm->n_cols = fm->n_id + fm->n_exp;

    slot_map map = {calloc((size_t)nv, sizeof(int)), NULL, 0, 0};
    if (!map.of_vertex) {
        fr_fit_model_free(fm);
        return fr_nomem(ctx, "the fit model");
    }
    for (int v = 0; v < nv; v++) map.of_vertex[v] = -1;
    frig_status s = FRIG_OK;
    const int32_t *lm = frig_model_landmarks(model);
    fr_fit_landmark_vertices(ctx, model, fm->landmark_vertex);
    for (int k = 0; k < FR_LANDMARKS && !s; k++)
        if ((fm->landmark_slot[k] = slot_add(&map, fm->landmark_vertex[k])) < 0) s = fr_nomem(ctx, "the fit model");

    /* Band limits from the neutral's landmarks: chin (8) and the eyes' lower lids (41, 46). */
    const float *neutral = frig_model_neutral(model);
    band bd;
    bd.chin_y = neutral[3 * (size_t)lm[8] + 1];
    bd.eye_y = 0.5 * (neutral[3 * (size_t)lm[41] + 1] + neutral[3 * (size_t)lm[46] + 1]);
    for (int e = 0; e < 2; e++) {
        bd.eye[e][0] = bd.eye[e][1] = 0;
        for (int k = 36 + 6 * e; k < 42 + 6 * e; k++)
            for (int c = 0; c < 2; c++) bd.eye[e][c] += neutral[3 * (size_t)lm[k] + c] / 6;
    }
    fm->side0_sign = neutral[3 * (size_t)lm[0]] < 0 ? -1 : 1;

    int narrow = frig_model_region_find(model, "narrow_face");
    int band_first = 0, band_count = nv;
    if (narrow >= 0) frig_model_region(model, narrow, NULL, &band_first, &band_count);
    if (!s) s = build_rows(ctx, fm, &map, lm, neutral, band_first, band_count, &bd);
    /* Triangles with all three corners in slots: normals for the silhouette test. */
    if (!s) {
        int nt = frig_model_triangle_count(model);
        const int32_t *tri = frig_model_triangles(model);
        fm->tris = malloc(sizeof(int) * 3 * (size_t)(nt > 0 ? nt : 1));
        if (!fm->tris) s = fr_nomem(ctx, "the fit model");
        for (int t = 0; t < nt && !s; t++) {
            int a = map.of_vertex[tri[3 * t]], b = map.of_vertex[tri[3 * t + 1]], c = map.of_vertex[tri[3 * t + 2]];
            if (a < 0 || b < 0 || c < 0) continue;
            fm->tris[3 * fm->n_tris] = a;
            fm->tris[3 * fm->n_tris + 1] = b;
            fm->tris[3 * fm->n_tris + 2] = c;
            fm->n_tris++;
        }
    }
    fm->n_slots = map.count;
    fm->slot_vertex = map.vertex;
    free(map.of_vertex);
    if (!s) s = build_adjacency(ctx, fm);
    if (!s) s = gather_basis(ctx, fm);
    if (!s && fm->n_id > 0) {
        fm->size_gradient = malloc(sizeof(double) * (size_t)fm->n_id);
        s = fm->size_gradient ? fr_face_size_gradient(ctx, model, fm->n_id, fm->size_gradient)
                              : fr_nomem(ctx, "the fit model");
    }
    if (s) fr_fit_model_free(fm);
    return s;
}

frig_status fr_fit_model_build_rig(frig_ctx *ctx, const frig_model *model, const frig_rig *rig, fr_fit_model *fm) {
    if (frig_rig_vertex_count(rig) != frig_model_vertex_count(model))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a rig of %d vertices cannot be fitted with a model of %d",
                        frig_rig_vertex_count(rig), frig_model_vertex_count(model));
    /* The slots and rows come from the model (topology); the basis from the rig. */
    frig_status s = fr_fit_model_build(ctx, model, 0, fm);
    if (s) return s;
    fm->rig = rig;
    free(fm->mean);
    free(fm->basis);
    fm->mean = fm->basis = NULL;
    s = gather_basis(ctx, fm);
    if (s) fr_fit_model_free(fm);
    return s;
}

void fr_fit_model_free(fr_fit_model *fm) {
    free(fm->exp_index);
    free(fm->slot_vertex);
    free(fm->mean);
    free(fm->basis);
    free(fm->row_slots);
    free(fm->row_radius);
    free(fm->tris);
    free(fm->adj_start);
    free(fm->adj);
    free(fm->size_gradient);
    memset(fm, 0, sizeof *fm);
}

void fr_fit_model_eval_slots(const fr_fit_model *fm, const double *w, const int *slots, int n, double *out) {
    for (int k = 0; k < n; k++) {
        int s = slots[k];
        for (int c = 0; c < 3; c++)
            out[3 * k + c] = fm->mean[3 * s + c] + cblas_ddot(fm->n_cols, fr_fit_model_row(fm, s, c), 1, w, 1);
    }
}

void fr_fit_model_eval_all(const fr_fit_model *fm, const double *w, double *out) {
    memcpy(out, fm->mean, sizeof(double) * 3 * (size_t)fm->n_slots);
    cblas_dgemv(CblasRowMajor, CblasNoTrans, 3 * fm->n_slots, fm->n_cols, 1.0, fm->basis, fm->n_cols, w, 1, 1.0,
                out, 1);
}
