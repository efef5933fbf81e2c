/* A synthetic subject (paper section 7.2's ground truth, made outside the fitted model's
 * span): identity weights ~ N(0, s^2 I), a personal offset orthogonal to the identity modes,
 * its own expression deltas, a painted albedo, and what the renderer needs (the triangles
 * drawn, the face's outline part, the eyes). Deterministic in the seed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "model/model.h"
#include "rig/rig.h"
#include "mesh/eye_frame.h"
#include "synth/synth.h"

/* Independent streams of a subject's seed. */
enum { STREAM_IDENTITY = 1, STREAM_OFFSET = 2, STREAM_EXPRESSIONS = 3, STREAM_ALBEDO = 4, STREAM_EYES = 5,
       STREAM_TORSO = 6 };

#define AO_FLOOR 0.2f /* albedo factor of a fully occluded vertex */
#define FOREHEAD 1.35 /* chin to the top of the forehead, in chin-to-brow lengths */

static int hidden_material(const char *name) {
    /* transparent overlays, the iris inside the sclera's cornea, and the lash strips (drawn as
     * opaque strips they look like black wedges; the painted lash line stands in for them) */
    static const char *const hidden[] = {"M_EyeOcclusion", "M_LacrimalFluid", "M_EyeBlend", "M_IrisLeft",
                                         "M_IrisRight",    "M_EyeLashes"};
    for (size_t i = 0; i < sizeof hidden / sizeof hidden[0]; i++)
        if (strcmp(name, hidden[i]) == 0) return 1;
    return 0;
}

/* The part of the face whose outline a landmark detector follows, in the mean face's (x, y):
 * inside the jaw line (landmarks 0..16, closed by lines straight up from its ends), or above
 * landmark 3 (the side of the cheek toward the ear, which outlines a turned face). */
static int outline_face(const frig_model *m, const float *x) {
    if (x[1] > m->neutral[3 * (size_t)m->landmarks[3] + 1]) return 1;
    double px[19], py[19];
    for (int k = 0; k < 17; k++) {
        const float *q = m->neutral + 3 * (size_t)m->landmarks[k];
        px[k] = q[0], py[k] = q[1];
    }
    px[17] = px[16], py[17] = py[16] + 1.0;
    px[18] = px[0], py[18] = py[0] + 1.0;
    int in = 0;
    for (int i = 0, j = 18; i < 19; j = i++)
        if ((py[i] > x[1]) != (py[j] > x[1]) && x[0] < (px[j] - px[i]) * (x[1] - py[i]) / (py[j] - py[i]) + px[i])
            in = !in;
    return in;
}

static frig_status drawn_triangles(frig_ctx *ctx, const frig_model *m, frig_synth_subject *s,
                                   const int32_t *torso, int torso_nt) {
    const fr_topology *t = &m->topo;
    int narrow0, nnarrow, eye0[2], neye[2];
    if (!fr_synth_region(m, "narrow_face", &narrow0, &nnarrow) && !fr_synth_region(m, "face", &narrow0, &nnarrow))
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model has no 'face' region");
    if (!fr_synth_region(m, "eyeball_left", &eye0[0], &neye[0])) eye0[0] = neye[0] = 0;
    if (!fr_synth_region(m, "eyeball_right", &eye0[1], &neye[1])) eye0[1] = neye[1] = 0;
    size_t most = (size_t)t->triangle_count + (size_t)torso_nt;
    s->tris = malloc(sizeof *s->tris * 3 * most);
    s->outline_tri = calloc(most + 1, 1);
    s->eye_tri = calloc(most + 1, 1);
    uint8_t *jaw = calloc((size_t)t->vertex_count, 1);
    if (!s->tris || !s->outline_tri || !s->eye_tri || !jaw) {
        free(jaw);
        return fr_nomem(ctx, "the subject's triangles");
    }
    for (int v = narrow0; v < narrow0 + nnarrow; v++) jaw[v] = (uint8_t)outline_face(m, m->neutral + 3 * (size_t)v);
    s->nt = 0;
    for (int k = 0; k < t->triangle_count; k++) {
        if (hidden_material(t->material_names[t->triangle_materials[k]])) continue;
        const int32_t *tr = t->triangles + 3 * (size_t)k;
        memcpy(s->tris + 3 * (size_t)s->nt, tr, 3 * sizeof *tr);
        s->outline_tri[s->nt] = jaw[tr[0]] && jaw[tr[1]] && jaw[tr[2]];
        s->eye_tri[s->nt] = 0;
        for (int e = 0; e < 2; e++)
            if (tr[0] >= eye0[e] && tr[0] < eye0[e] + neye[e]) s->eye_tri[s->nt] = (uint8_t)(1 + e);
        s->nt++;
    }
    s->nt_head = s->nt;
    for (int k = 0; k < 3 * torso_nt; k++) s->tris[3 * (size_t)s->nt + (size_t)k] = torso[k] + s->nv;
    s->nt += torso_nt;
    free(jaw);
    return FRIG_OK;
}

/* The torso's vertices after the head's, its triangles after the head's, its clothing albedo
 * (a little darker toward the bottom). */
static frig_status add_torso(frig_ctx *ctx, const frig_model *m, frig_synth_subject *s) {
    fr_rng rng;
    fr_rng_seed(&rng, fr_seed_mix(s->seed, STREAM_TORSO));
    int tnv = 0, tnt = 0;
    int32_t *ttris = NULL;
    frig_status st = fr_synth_torso(ctx, s, &rng, &s->torso_xyz, &tnv, &ttris, &tnt);
    if (st) return st;
    s->nv_render = s->nv + tnv;
    float *albedo = realloc(s->albedo, sizeof *albedo * 3 * (size_t)s->nv_render);
    if (!albedo) st = fr_nomem(ctx, "the torso's albedo");
    else s->albedo = albedo;
    for (int v = 0; !st && v < tnv; v++) {
        double shade = 1.0 + 2.0 * (s->torso_xyz[3 * (size_t)v + 1] + 0.12);
        for (int c = 0; c < 3; c++)
            s->albedo[3 * (size_t)(s->nv + v) + c] =
                (float)(fr_srgb_to_linear(s->cloth_srgb[c] / 255.0) * (shade < 0.4 ? 0.4 : shade));
    }
    if (!st) st = drawn_triangles(ctx, m, s, ttris, tnt);
    free(ttris);
    return st;
}

/* Eyeball centres and gaze axes from the subject's neutral (fr_eye_frame: through the cornea). */
static void eyes(const frig_model *m, const float *neutral, frig_synth_subject *s) {
    static const char *const names[2] = {"eyeball_left", "eyeball_right"};
    fr_rng rng;
    fr_rng_seed(&rng, fr_seed_mix(s->seed, STREAM_EYES));
    s->iris_radius = 0.0055 + 0.0006 * fr_rng_uniform(&rng);
    s->pupil_radius = 0.0013 + 0.0008 * fr_rng_uniform(&rng);
    for (int e = 0; e < 2; e++) fr_eye_frame(&m->topo, neutral, names[e], s->eye_centre[e], s->eye_axis[e]);
    for (int i = 0; i < 3; i++) {
        s->iris_albedo[i] = fr_srgb_to_linear(s->iris_srgb[i] / 255.0);
        s->sclera_albedo[i] = fr_srgb_to_linear((i == 0 ? 228.0 : i == 1 ? 220.0 : 214.0) / 255.0);
    }
}

static void face_frame(const frig_model *m, const float *neutral, frig_synth_subject *s) {
    const float *chin = neutral + 3 * (size_t)m->landmarks[8], *b1 = neutral + 3 * (size_t)m->landmarks[19],
                *b2 = neutral + 3 * (size_t)m->landmarks[24];
    double up[3], len = 0.0;
    for (int d = 0; d < 3; d++) up[d] = 0.5 * (b1[d] + b2[d]) - chin[d], len += up[d] * up[d];
    s->face_height = FOREHEAD * sqrt(len);
    for (int d = 0; d < 3; d++) s->face_centre[d] = chin[d] + 0.5 * FOREHEAD * up[d];
}

/* Outward normals of the jaw line in the mean face's (x, y) plane, away from the nose. */
static void jaw_normals(const frig_model *m, frig_synth_subject *s) {
    const float *c = m->neutral + 3 * (size_t)m->landmarks[30];
    for (int k = 0; k < 17; k++) {
        const float *a = m->neutral + 3 * (size_t)m->landmarks[k > 0 ? k - 1 : 0],
                    *b = m->neutral + 3 * (size_t)m->landmarks[k < 16 ? k + 1 : 16],
                    *q = m->neutral + 3 * (size_t)m->landmarks[k];
        double nx = b[1] - a[1], ny = -(b[0] - a[0]), len = sqrt(nx * nx + ny * ny);
        if ((q[0] - c[0]) * nx + (q[1] - c[1]) * ny < 0.0) nx = -nx, ny = -ny;
        s->jaw_normal[k][0] = len > 0.0 ? nx / len : 0.0;
        s->jaw_normal[k][1] = len > 0.0 ? ny / len : 0.0;
        s->jaw_normal[k][2] = 0.0;
    }
}

static frig_status check_model(frig_ctx *ctx, const frig_model *m) {
    if (!m) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_synth_subject_create: no model");
    if (m->landmark_count != FR_SYNTH_LANDMARKS)
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model has %d landmarks; synthetic photos need 68",
                        m->landmark_count);
    if (m->expression_count < 1)
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model has no expressions to make a subject's rig of");
    return FRIG_OK;
}

static frig_status alloc_subject(frig_ctx *ctx, const frig_model *m, frig_synth_subject *s) {
    s->nv = m->topo.vertex_count;
    s->shape_count = m->expression_count;
    s->identity_count = m->identity_count;
    s->albedo = malloc(sizeof *s->albedo * 3 * (size_t)s->nv);
    s->hair = calloc((size_t)s->nv, sizeof *s->hair);
    s->skin = calloc((size_t)s->nv, 1);
    s->fitting = malloc((size_t)s->shape_count);
    s->identity = calloc((size_t)s->identity_count + 1, sizeof *s->identity);
    s->shape_scale = calloc((size_t)s->shape_count, sizeof *s->shape_scale);
    s->shape_field_rel = calloc((size_t)s->shape_count, sizeof *s->shape_field_rel);
    if (!s->albedo || !s->hair || !s->skin || !s->fitting || !s->identity || !s->shape_scale || !s->shape_field_rel)
        return fr_nomem(ctx, "a synthetic subject");
    for (int k = 0; k < s->shape_count; k++) s->fitting[k] = (uint8_t)(m->expression_fitting[k] != 0);
    memcpy(s->landmarks, m->landmarks, sizeof s->landmarks);
    return FRIG_OK;
}

/* Identity, offset and expressions make the true rig. */
static frig_status build_rig(frig_ctx *ctx, const frig_model *m, frig_synth_subject *s) {
    size_t n3 = 3 * (size_t)s->nv;
    float *neutral = malloc(sizeof *neutral * n3), *deltas = malloc(sizeof *deltas * n3 * (size_t)s->shape_count);
    if (!neutral || !deltas) {
        free(neutral), free(deltas);
        return fr_nomem(ctx, "the subject's rig");
    }
    fr_rng rng;
    fr_rng_seed(&rng, fr_seed_mix(s->seed, STREAM_IDENTITY));
    s->identity_scale = 0.8 + 0.2 * fr_rng_uniform(&rng);
    for (int k = 0; k < s->identity_count; k++) s->identity[k] = s->identity_scale * fr_rng_normal(&rng);
    frig_status st = frig_model_eval(ctx, m, s->identity, NULL, neutral);
    if (!st) {
        fr_rng_seed(&rng, fr_seed_mix(s->seed, STREAM_OFFSET));
        st = fr_synth_offset(ctx, m, s, &rng, fr_param(ctx, FRIG_PARAM_SYNTH_OFFSET_MM), neutral);
    }
    if (!st) {
        memcpy(deltas, m->expressions, sizeof *deltas * n3 * (size_t)s->shape_count);
        fr_rng_seed(&rng, fr_seed_mix(s->seed, STREAM_EXPRESSIONS));
        st = fr_synth_perturb_expressions(ctx, m, s, &rng, neutral, deltas);
    }
    if (!st)
        st = fr_rig_build(ctx, &m->topo, s->shape_count, neutral, deltas, m->expression_blob,
                          m->expression_blob_size, &s->rig);
    if (!st) {
        face_frame(m, neutral, s);
        fr_rng_seed(&rng, fr_seed_mix(s->seed, STREAM_ALBEDO));
        st = fr_synth_paint_albedo(ctx, m, s, &rng);
    }
    if (!st) eyes(m, neutral, s);
    if (!st) jaw_normals(m, s);
    free(neutral), free(deltas);
    return st;
}

/* Darken the albedo where the neutral head occludes itself (eye sockets, nostrils, mouth). */
static frig_status bake_occlusion(frig_ctx *ctx, frig_synth_subject *s) {
    float *ao = malloc(sizeof *ao * (size_t)s->nv);
    if (!ao) return fr_nomem(ctx, "ambient occlusion");
    frig_status st = fr_synth_ambient_occlusion(ctx, frig_rig_neutral(s->rig), s->nv, s->tris, s->nt_head, ao);
    for (int v = 0; !st && v < s->nv; v++)
        for (int c = 0; c < 3; c++) s->albedo[3 * (size_t)v + c] *= AO_FLOOR + (1.0f - AO_FLOOR) * ao[v];
    free(ao);
    return st;
}

frig_status frig_synth_subject_create(frig_ctx *ctx, const frig_model *model, uint64_t seed,
                                      frig_synth_subject **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_synth_subject_create: out is NULL");
    *out = NULL;
    frig_status st = check_model(ctx, model);
    if (st) return st;
    frig_synth_subject *s = calloc(1, sizeof *s);
    if (!s) return fr_nomem(ctx, "a synthetic subject");
    s->seed = seed;
    st = alloc_subject(ctx, model, s);
    if (!st) st = build_rig(ctx, model, s);
    if (!st) st = add_torso(ctx, model, s);
    if (!st) st = bake_occlusion(ctx, s);
    if (st) {
        frig_synth_subject_free(s);
        return st;
    }
    *out = s;
    return FRIG_OK;
}

void frig_synth_subject_free(frig_synth_subject *s) {
    if (!s) return;
    frig_rig_free(s->rig);
    free(s->albedo), free(s->hair), free(s->skin), free(s->torso_xyz), free(s->tris), free(s->outline_tri), free(s->eye_tri), free(s->fitting);
    free(s->identity), free(s->shape_scale), free(s->shape_field_rel);
    free(s);
}

const frig_rig *frig_synth_subject_rig(const frig_synth_subject *s) { return s ? s->rig : NULL; }

int frig_synth_subject_identity(const frig_synth_subject *s, const double **weights) {
    if (weights) *weights = s ? s->identity : NULL;
    return s ? s->identity_count : 0;
}

double frig_synth_subject_offset_rms_mm(const frig_synth_subject *s) { return s ? s->offset_rms_mm : NAN; }
