/* The parameters of one synthetic photo, drawn from its seed (paper section 7.2's synthetic
 * data, made harder: photos "in the wild"): head pose, expression mix, perspective camera,
 * spherical-harmonics lighting, background, sensor noise, JPEG quality, intended failures. */
#include <math.h>
#include <string.h>

#include "rig/rig.h"
#include "synth/synth.h"

#define DEG (3.14159265358979323846 / 180.0)
#define NEUTRAL_SHARE 0.15 /* photos with no expression at all */
#define METERED_SKIN 0.4   /* linear luminance the exposure brings the skin albedo toward */

static double uniform(fr_rng *r, double lo, double hi) { return lo + (hi - lo) * fr_rng_uniform(r); }

static int is_active(const fr_synth_photo *p, int k) {
    for (int i = 0; i < p->n_active; i++)
        if (p->active[i] == k) return i;
    return -1;
}

/* Eye turns are linear in the rig, so a strong one pushes the cornea through the lid: at most
 * one per eye, weight at most EYE_LOOK_MAX. */
#define EYE_LOOK_MAX 0.7

static int eye_look_side(const char *name) {
    if (strncmp(name, "eyeLook", 7) != 0) return -1;
    size_t n = strlen(name);
    return n > 2 && name[n - 2] == '_' ? name[n - 1] : -1;
}

/* Would shape k add a second eye turn to an eye? */
static int second_eye_look(const frig_synth_subject *s, const fr_synth_photo *p, int k) {
    int side = eye_look_side(frig_rig_shape_name(s->rig, k));
    if (side < 0) return 0;
    for (int i = 0; i < p->n_active; i++)
        if (eye_look_side(frig_rig_shape_name(s->rig, p->active[i])) == side) return 1;
    return 0;
}

/* 0-4 distinct fitting expressions with weights in [0.2, 1] (eye turns: see above); mouthClose
 * (lips pressed while the jaw opens) brings jawOpen along at least as strong. */
static void draw_expression(const frig_synth_subject *s, fr_rng *r, fr_synth_photo *p) {
    int nfit = 0;
    for (int k = 0; k < s->shape_count; k++) nfit += s->fitting[k];
    p->n_active = 0;
    if (nfit == 0 || fr_rng_uniform(r) < NEUTRAL_SHARE) return;
    int want = 1 + (int)fr_rng_below(r, 4);
    for (int tries = 0; p->n_active < want && tries < 64; tries++) {
        int pick = (int)fr_rng_below(r, (uint64_t)nfit), k = 0;
        for (int seen = -1; k < s->shape_count; k++)
            if (s->fitting[k] && ++seen == pick) break;
        double w = uniform(r, 0.2, 1.0);
        if (is_active(p, k) >= 0 || second_eye_look(s, p, k)) continue;
        if (eye_look_side(frig_rig_shape_name(s->rig, k)) >= 0) w = 0.2 + (w - 0.2) * (EYE_LOOK_MAX - 0.2) / 0.8;
        p->active[p->n_active] = k;
        p->weight[p->n_active++] = w;
    }
    int close = frig_rig_shape_find(s->rig, "mouthClose"), jaw = frig_rig_shape_find(s->rig, "jawOpen");
    int ic = close >= 0 ? is_active(p, close) : -1;
    if (ic < 0 || jaw < 0) return;
    int ij = is_active(p, jaw);
    if (ij < 0) {
        ij = p->n_active++;
        p->active[ij] = jaw;
        p->weight[ij] = 0.0;
    }
    if (p->weight[ij] < p->weight[ic]) p->weight[ij] = fmin(1.0, p->weight[ic] + uniform(r, 0.0, 0.3));
}

static void draw_pose(fr_rng *r, double max_yaw, int extreme, fr_synth_photo *p) {
    if (extreme) p->yaw = (fr_rng_uniform(r) < 0.5 ? -1.0 : 1.0) * uniform(r, 75.0, 90.0);
    else p->yaw = uniform(r, -max_yaw, max_yaw);
    p->pitch = uniform(r, -20.0, 20.0);
    p->roll = uniform(r, -12.0, 12.0);
    fr_rotation_from_euler(p->yaw * DEG, p->pitch * DEG, p->roll * DEG, p->R);
}

/* Focal length 35-100 mm (35 mm equivalent, on the longer side); the face (chin to the top of
 * the forehead) 25-60% of the image height, placed anywhere it fits. */
static void draw_camera(const frig_synth_subject *s, fr_rng *r, fr_synth_photo *p) {
    int side = p->width > p->height ? p->width : p->height;
    p->focal_mm = uniform(r, 35.0, 100.0);
    p->cam = fr_camera_perspective(p->focal_mm / 36.0 * side, p->width, p->height);
    p->face_frac = uniform(r, 0.25, 0.60);
    double fh = p->face_frac * p->height, z = p->cam.f * s->face_height / fh;
    double room_u = 0.5 * p->width - 0.45 * fh, room_v = 0.5 * p->height - 0.55 * fh;
    double u0 = p->cam.cx + (room_u > 0.0 ? room_u : 0.0) * uniform(r, -0.9, 0.9);
    double v0 = p->cam.cy + (room_v > 0.0 ? room_v : 0.0) * uniform(r, -0.9, 0.9);
    double rc[3];
    fr_mat3_apply(p->R, s->face_centre, rc);
    p->t[0] = z * (u0 - p->cam.cx) / p->cam.f - rc[0];
    p->t[1] = z * (v0 - p->cam.cy) / p->cam.f - rc[1];
    p->t[2] = z - rc[2];
}

/* A dominant light from the camera's side of the head (mostly from above), an ambient term,
 * both slightly coloured; the exposure scales the lot, half-way metered on the skin as a
 * camera's face-priority metering does (dark skin is not rendered nearly black). */
static void draw_lighting(const frig_synth_subject *s, fr_rng *r, fr_synth_photo *p) {
    double d[3] = {uniform(r, -0.9, 0.9), uniform(r, -0.9, 0.4), -uniform(r, 0.35, 1.0)};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; i++) p->light_dir[i] = d[i] / len;
    double ambient = uniform(r, 0.25, 0.55);
    p->light_ratio = (1.0 - ambient) / ambient;
    double skin = 0.2126 * fr_srgb_to_linear(s->skin_srgb[0] / 255.0) + 0.7152 * fr_srgb_to_linear(s->skin_srgb[1] / 255.0) +
                  0.0722 * fr_srgb_to_linear(s->skin_srgb[2] / 255.0);
    p->exposure = uniform(r, 0.8, 1.15) * sqrt(METERED_SKIN / fmax(skin, 0.02));
    for (int c = 0; c < 3; c++) {
        double tint_d = 1.0 + uniform(r, -0.08, 0.08), tint_a = 1.0 + uniform(r, -0.08, 0.08);
        fr_sh_irradiance_coeffs(p->light_dir, p->exposure * (1.0 - ambient) * tint_d, p->exposure * ambient * tint_a,
                                p->sh[c]);
        p->direct_rgb[c] = p->exposure * (1.0 - ambient) * tint_d;
        fr_sh_irradiance_coeffs(p->light_dir, p->direct_rgb[c], 0.0, p->sh_direct[c]);
    }
}

void fr_synth_photo_one_light(const frig_synth_subject *s, fr_synth_photo *p) {
    fr_rng r;
    fr_rng_seed(&r, s->seed ^ 0x6c1647u); /* a stream of the subject's own */
    draw_lighting(s, &r, p);
}

/* Dark glasses: the lenses' size and height jitter, a dark tinted lens, a frame colour and the
 * strength of the sky reflected in the lenses. */
static void draw_sunglasses(fr_rng *r, fr_synth_photo *p) {
    for (int i = 0; i < 4; i++) p->sg_jitter[i] = uniform(r, -1.0, 1.0);
    double dark = uniform(r, 0.008, 0.04), tint[3] = {uniform(r, 0.7, 1.3), uniform(r, 0.7, 1.3), uniform(r, 0.7, 1.3)};
    for (int c = 0; c < 3; c++) p->sg_lens[c] = dark * tint[c];
    int metal = fr_rng_uniform(r) < 0.4;
    for (int c = 0; c < 3; c++) p->sg_frame[c] = metal ? uniform(r, 0.3, 0.6) : uniform(r, 0.01, 0.06);
    p->sg_glare = uniform(r, 0.0, 0.12);
}

/* An exposure failure scales the whole photo: 8-30x too dark, or 4-10x too bright. */
static double draw_gain(fr_rng *r, int failure) {
    if (failure == FRIG_SYNTH_FAILURE_UNDEREXPOSED) return 1.0 / uniform(r, 8.0, 30.0);
    if (failure == FRIG_SYNTH_FAILURE_OVEREXPOSED) return uniform(r, 4.0, 10.0);
    return 1.0;
}

/* Hard shadows in a share of the photos (a key light on a clear day, a flash off the camera);
 * oily to matte skin: a Blinn-Phong lobe whose peak is 3-15% of the key light. */
void fr_synth_photo_effects(fr_synth_photo *p, double shadow_rate, double specular) {
    fr_rng r;
    fr_rng_seed(&r, fr_seed_mix(p->seed, 0x5adeULL));
    p->shadows = fr_rng_uniform(&r) < shadow_rate;
    p->spec_ks = specular * uniform(&r, 0.03, 0.15);
    p->spec_shininess = uniform(&r, 12.0, 40.0);
}

static void draw_background(fr_rng *r, fr_synth_photo *p) {
    for (int k = 0; k < 2; k++)
        for (int c = 0; c < 3; c++) p->bg_colour[k][c] = fr_srgb_to_linear(uniform(r, 0.08, 0.92));
    p->bg_angle = uniform(r, 0.0, 6.283185307179586);
    p->bg_clutter = fr_rng_uniform(r) < 0.3;
    p->bg_seed = fr_rng_next(r);
}

static void draw_occluder(const frig_synth_subject *s, fr_rng *r, fr_synth_photo *p) {
    p->occ_shape = (int)fr_rng_below(r, 3);
    p->occ_over = (int)fr_rng_below(r, 2);
    for (int i = 0; i < 4; i++) p->occ_jitter[i] = uniform(r, -1.0, 1.0);
    if (p->occ_shape == 2) { /* a hand: the subject's own skin tone, a little varied */
        double f = uniform(r, 0.85, 1.1);
        for (int c = 0; c < 3; c++) p->occ_colour[c] = fr_srgb_to_linear(fmin(1.0, s->skin_srgb[c] * f / 255.0));
    } else {
        for (int c = 0; c < 3; c++) p->occ_colour[c] = fr_srgb_to_linear(uniform(r, 0.05, 0.9));
    }
}

void fr_synth_photo_draw(const frig_synth_subject *s, uint64_t seed, int width, int height, int failure,
                         double max_yaw_deg, double failure_rate, fr_synth_photo *p) {
    memset(p, 0, sizeof *p);
    fr_rng r;
    fr_rng_seed(&r, seed);
    p->seed = seed;
    p->width = width;
    p->height = height;
    if (failure == FRIG_SYNTH_FAILURE_AUTO)
        failure = fr_rng_uniform(&r) < failure_rate ? 1 + (int)fr_rng_below(&r, FR_SYNTH_FAILURE_KINDS)
                                                     : FRIG_SYNTH_FAILURE_NONE;
    p->failure = failure;
    draw_pose(&r, max_yaw_deg, failure == FRIG_SYNTH_FAILURE_EXTREME_POSE, p);
    draw_expression(s, &r, p);
    draw_camera(s, &r, p);
    draw_lighting(s, &r, p);
    draw_background(&r, p);
    draw_occluder(s, &r, p);
    p->jpeg_quality = 70 + (int)fr_rng_below(&r, 26);
    p->noise_sigma = uniform(&r, 0.5, 3.0);
    p->noise_seed = fr_rng_next(&r);
    draw_sunglasses(&r, p);
    p->gain = draw_gain(&r, failure);
}
