/* The truth of one synthetic photo, what the fit (paper sections 4.3-4.4: pose, camera,
 * expression weights, landmarks) and shape from shading (section 5.1: depth, SH lighting) are
 * measured against: accessors, and the JSON + raw float32 depth files (docs/synth.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/file.h"
#include "io/json_writer.h"
#include "rig/rig.h"
#include "synth/synth.h"

#define TRUTH_FORMAT "frig-synth-truth 1"

frig_status fr_synth_truth_new(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *p,
                               frig_synth_truth **out) {
    *out = NULL;
    frig_synth_truth *t = calloc(1, sizeof *t);
    if (!t) return fr_nomem(ctx, "a photo's truth");
    t->photo = *p;
    t->shape_count = s->shape_count;
    t->expression = calloc((size_t)s->shape_count + 1, sizeof *t->expression);
    t->shape_names = calloc((size_t)s->shape_count + 1, sizeof *t->shape_names);
    t->names_blob = malloc(s->rig->name_blob_size + 1);
    t->depth = calloc((size_t)p->width * (size_t)p->height, sizeof *t->depth);
    t->mask = calloc((size_t)p->width * (size_t)p->height + 1, 1);
    if (!t->expression || !t->shape_names || !t->names_blob || !t->depth || !t->mask) {
        frig_synth_truth_free(t);
        return fr_nomem(ctx, "a photo's truth");
    }
    memcpy(t->names_blob, s->rig->name_blob, s->rig->name_blob_size);
    for (int k = 0; k < s->shape_count; k++)
        t->shape_names[k] = t->names_blob + (s->rig->shape_names[k] - s->rig->name_blob);
    for (int a = 0; a < p->n_active; a++) t->expression[p->active[a]] = p->weight[a];
    memcpy(t->landmark_vertices, s->landmarks, sizeof t->landmark_vertices);
    fr_synth_landmarks_none(&t->lm);
    *out = t;
    return FRIG_OK;
}

void frig_synth_truth_free(frig_synth_truth *t) {
    if (!t) return;
    free(t->expression), free(t->shape_names), free(t->names_blob), free(t->depth), free(t->mask);
    free(t);
}

frig_synth_failure frig_synth_truth_failure(const frig_synth_truth *t) {
    return t ? (frig_synth_failure)t->photo.failure : FRIG_SYNTH_FAILURE_NONE;
}

const double *frig_synth_truth_landmarks(const frig_synth_truth *t, int detector_like) {
    if (!t || !t->has_face) return NULL;
    return detector_like ? t->lm.detector : t->lm.exact;
}

const uint8_t *frig_synth_truth_visible(const frig_synth_truth *t) { return t ? t->lm.visible : NULL; }

void frig_synth_truth_pose(const frig_synth_truth *t, double R[9], double tr[3]) {
    for (int i = 0; i < 9; i++) R[i] = t && t->has_face ? t->photo.R[i] : 0.0;
    for (int i = 0; i < 3; i++) tr[i] = t && t->has_face ? t->photo.t[i] : 0.0;
}

void frig_synth_truth_camera(const frig_synth_truth *t, double *f, double *cx, double *cy) {
    int ok = t && t->has_face;
    if (f) *f = ok ? t->photo.cam.f : 0.0;
    if (cx) *cx = ok ? t->photo.cam.cx : 0.0;
    if (cy) *cy = ok ? t->photo.cam.cy : 0.0;
}

const double *frig_synth_truth_expression(const frig_synth_truth *t) { return t ? t->expression : NULL; }

const float *frig_synth_truth_depth(const frig_synth_truth *t, int *width, int *height) {
    if (width) *width = t ? t->photo.width : 0;
    if (height) *height = t ? t->photo.height : 0;
    return t ? t->depth : NULL;
}

int frig_synth_truth_jpeg_quality(const frig_synth_truth *t) { return t ? t->photo.jpeg_quality : 0; }

const uint8_t *frig_synth_truth_mask(const frig_synth_truth *t, int *width, int *height) {
    if (width) *width = t ? t->photo.width : 0;
    if (height) *height = t ? t->photo.height : 0;
    return t ? t->mask : NULL;
}

const char *frig_synth_failure_name(int failure) {
    static const char *const names[] = {"none",       "occluder",     "extreme_pose", "no_face",
                                        "sunglasses", "underexposed", "overexposed"};
    return failure >= 0 && failure <= FR_SYNTH_FAILURE_KINDS ? names[failure] : NULL;
}

void fr_synth_json_numbers(fr_json *j, const char *key, const double *v, int n) {
    fr_json_array(j, key, 1);
    for (int i = 0; i < n; i++) fr_json_number(j, NULL, v[i]);
    fr_json_end(j);
}

static void points(fr_json *j, const char *key, const double *xy) {
    fr_json_array(j, key, 0);
    for (int k = 0; k < FR_SYNTH_LANDMARKS; k++) fr_synth_json_numbers(j, NULL, xy + 2 * k, 2);
    fr_json_end(j);
}

static void write_pose_camera(fr_json *j, const frig_synth_truth *t) {
    const fr_synth_photo *p = &t->photo;
    fr_json_object(j, "pose");
    fr_synth_json_numbers(j, "R", p->R, 9);
    fr_synth_json_numbers(j, "t", p->t, 3);
    fr_json_number(j, "yaw_deg", p->yaw);
    fr_json_number(j, "pitch_deg", p->pitch);
    fr_json_number(j, "roll_deg", p->roll);
    fr_json_end(j);
    fr_json_object(j, "camera");
    fr_json_string(j, "model", "perspective");
    fr_json_number(j, "f", p->cam.f);
    fr_json_number(j, "cx", p->cam.cx);
    fr_json_number(j, "cy", p->cam.cy);
    fr_json_number(j, "focal_mm_35", p->focal_mm);
    fr_json_number(j, "face_height_share", p->face_frac);
    fr_json_end(j);
}

static void write_expression_lighting(fr_json *j, const frig_synth_truth *t) {
    const fr_synth_photo *p = &t->photo;
    fr_json_object(j, "expression");
    for (int a = 0; a < p->n_active; a++) fr_json_number(j, t->shape_names[p->active[a]], p->weight[a]);
    fr_json_end(j);
    fr_json_object(j, "lighting");
    fr_json_string(j, "model", "albedo * sum_k (sh[c][k] - (1 - visibility) sh_key[c][k]) Y_k(n) + highlight, "
                               "n in camera coordinates (docs/synth.md)");
    double v[9];
    fr_json_array(j, "sh", 0);
    for (int c = 0; c < 3; c++) {
        for (int k = 0; k < 9; k++) v[k] = p->gain * p->sh[c][k];
        fr_synth_json_numbers(j, NULL, v, 9);
    }
    fr_json_end(j);
    fr_json_array(j, "sh_key", 0);
    for (int c = 0; c < 3; c++) {
        for (int k = 0; k < 9; k++) v[k] = p->gain * p->sh_direct[c][k];
        fr_synth_json_numbers(j, NULL, v, 9);
    }
    fr_json_end(j);
    fr_synth_json_numbers(j, "direction", p->light_dir, 3);
    fr_json_number(j, "direct_to_ambient", p->light_ratio);
    fr_json_number(j, "exposure", p->exposure);
    fr_json_number(j, "gain", p->gain);
    fr_json_bool(j, "cast_shadows", p->shadows);
    fr_json_object(j, "specular");
    fr_json_number(j, "ks", p->spec_ks);
    fr_json_number(j, "shininess", p->spec_shininess);
    fr_json_end(j);
    fr_json_end(j);
}

static void write_landmarks(fr_json *j, const frig_synth_truth *t) {
    const fr_synth_landmarks *lm = &t->lm;
    fr_json_object(j, "landmarks");
    fr_json_array(j, "vertices", 1);
    for (int k = 0; k < FR_SYNTH_LANDMARKS; k++) fr_json_int(j, NULL, t->landmark_vertices[k]);
    fr_json_end(j);
    points(j, "projected", lm->exact);
    points(j, "detector_like", lm->detector);
    fr_json_array(j, "visible", 1);
    for (int k = 0; k < FR_SYNTH_LANDMARKS; k++) fr_json_int(j, NULL, lm->visible[k]);
    fr_json_end(j);
    fr_json_array(j, "jaw_moved", 1);
    for (int k = 0; k < 17; k++) fr_json_int(j, NULL, lm->jaw_moved[k]);
    fr_json_end(j);
    fr_synth_json_numbers(j, "face_box", lm->face_box, 4);
    fr_json_end(j);
}

static void write_occluder(fr_json *j, const fr_synth_photo *p) {
    static const char *const shapes[] = {"rectangle", "ellipse", "hand"};
    if (p->failure != FRIG_SYNTH_FAILURE_OCCLUDER) {
        fr_json_null(j, "occluder");
        return;
    }
    fr_json_object(j, "occluder");
    fr_json_string(j, "shape", shapes[p->occ_shape]);
    fr_json_string(j, "over", p->occ_over ? "mouth" : "eyes");
    fr_synth_json_numbers(j, "centre", p->occ_centre, 2);
    fr_synth_json_numbers(j, "half_axes", p->occ_axes, 2);
    fr_json_number(j, "angle_deg", p->occ_angle * 180.0 / 3.14159265358979323846);
    fr_synth_json_numbers(j, "colour_linear", p->occ_colour, 3);
    fr_json_end(j);
}

static void write_sunglasses(fr_json *j, const fr_synth_photo *p) {
    if (p->failure != FRIG_SYNTH_FAILURE_SUNGLASSES) {
        fr_json_null(j, "sunglasses");
        return;
    }
    fr_json_object(j, "sunglasses");
    fr_json_array(j, "lens_centres", 0);
    for (int e = 0; e < 2; e++) fr_synth_json_numbers(j, NULL, p->sg_centre[e], 2);
    fr_json_end(j);
    fr_json_array(j, "lens_half_axes", 0);
    for (int e = 0; e < 2; e++) fr_synth_json_numbers(j, NULL, p->sg_axes[e], 2);
    fr_json_end(j);
    fr_json_number(j, "angle_deg", p->sg_angle * 180.0 / 3.14159265358979323846);
    fr_synth_json_numbers(j, "lens_linear", p->sg_lens, 3);
    fr_synth_json_numbers(j, "frame_linear", p->sg_frame, 3);
    fr_json_end(j);
}

/* NAME.depth.f32 -> NAME.mask.u8, any other name + ".mask.u8" (a new string). */
static char *mask_path_for(const char *depth_path) {
    size_t n = strlen(depth_path), suffix = strlen(".depth.f32");
    char *m = malloc(n + 16);
    if (!m) return NULL;
    if (n > suffix && !strcmp(depth_path + n - suffix, ".depth.f32")) n -= suffix;
    memcpy(m, depth_path, n);
    strcpy(m + n, ".mask.u8");
    return m;
}

static void write_truth(fr_json *j, const frig_synth_truth *t, const char *photo, const char *depth_name) {
    const fr_synth_photo *p = &t->photo;
    fr_json_object(j, NULL);
    fr_json_string(j, "format", TRUTH_FORMAT);
    fr_json_string(j, "photo", photo ? photo : "");
    char seed[24];
    snprintf(seed, sizeof seed, "%016llx", (unsigned long long)p->seed);
    fr_json_string(j, "seed", seed);
    fr_json_int(j, "width", p->width);
    fr_json_int(j, "height", p->height);
    fr_json_string(j, "failure", frig_synth_failure_name(p->failure));
    fr_json_int(j, "jpeg_quality", p->jpeg_quality);
    fr_json_number(j, "noise_sigma", p->noise_sigma);
    if (t->has_face) {
        write_pose_camera(j, t);
        write_expression_lighting(j, t);
        write_landmarks(j, t);
    }
    write_occluder(j, p);
    write_sunglasses(j, p);
    if (depth_name) {
        fr_json_object(j, "depth");
        fr_json_string(j, "file", depth_name);
        fr_json_int(j, "width", p->width);
        fr_json_int(j, "height", p->height);
        fr_json_string(j, "format", "float32 little-endian, row-major, camera z in metres, 0 = no surface");
        fr_json_end(j);
        char *mask = mask_path_for(depth_name);
        fr_json_object(j, "mask");
        fr_json_string(j, "file", mask ? mask : "");
        fr_json_string(j, "format", "uint8, row-major, bits: 1 head, 2 skin, 4 cast shadow, 8 highlight, "
                                    "16 occluder or sunglasses, 32 hair (docs/synth.md)");
        fr_json_end(j);
        free(mask);
    }
    fr_json_end(j);
    fr_json_finish(j);
}

static frig_status save_depth(frig_ctx *ctx, const frig_synth_truth *t, const char *path) {
    size_t n = (size_t)t->photo.width * (size_t)t->photo.height;
    unsigned char *b = malloc(4 * n);
    if (!b) return fr_nomem(ctx, "the depth map");
    for (size_t i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &t->depth[i], 4);
        for (int k = 0; k < 4; k++) b[4 * i + (size_t)k] = (unsigned char)(u >> (8 * k));
    }
    frig_status s = fr_write_file_atomic(ctx, path, b, 4 * n);
    free(b);
    return s;
}

frig_status frig_synth_truth_save(frig_ctx *ctx, const frig_synth_truth *t, const char *photo, const char *json_path,
                                  const char *depth_path) {
    if (!t || !json_path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_synth_truth_save: no truth or path");
    frig_status s = depth_path ? save_depth(ctx, t, depth_path) : FRIG_OK;
    if (!s && depth_path) {
        char *mask = mask_path_for(depth_path);
        s = mask ? fr_write_file_atomic(ctx, mask, t->mask, (size_t)t->photo.width * (size_t)t->photo.height)
                 : fr_nomem(ctx, "a file name");
        free(mask);
    }
    fr_atomic_file af;
    if (!s) s = fr_atomic_open(ctx, json_path, &af);
    if (s) return s;
    fr_json j;
    fr_json_begin(&j, af.fp);
    write_truth(&j, t, photo, depth_path ? fr_path_base(depth_path) : NULL);
    return fr_atomic_commit(ctx, &af);
}
