/* Point clouds from frig synth's true depth maps, in place of the sfs stage's (what the
 * retarget stage can do with perfect clouds): for each fitted photo of a workspace made from
 * a synthetic subject's photos, the face pixels are unprojected from the true depth, given
 * normals from the depth map's neighbours and confidence 1, and moved into the head frame;
 * the result is saved as WORKSPACE/clouds/ (frig_clouds_save).
 *   realistic (default): the face pixels are those the workspace's current rig covers when
 *     rendered with the photo's fitted pose, camera and expression (as sfs selects them), and
 *     the surface is placed by the fitted pose and camera, as a perfect sfs anchored to the fit
 *     would recover it: each pixel on the fitted camera's ray, at the fitted head distance plus
 *     the true relief (true depth minus the true head distance) scaled by the fitted camera's
 *     metres per pixel over the true one's, so the cloud is the true surface scaled uniformly
 *     to the fit's size and carrying the fit's pose error.
 *   --like-clouds: only the face pixels within 2 pixels of the workspace's own clouds (and margins)
 *     seen through the fitted pose and camera (the sfs clouds' coverage with the true surface).
 *   --ideal: the face pixels of the true rig at the true pose, placed by the true pose and
 *     camera: the true surface in the true head frame.
 * Usage: truth_clouds WORKSPACE [--ideal] [--like-clouds] [--stride N] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frig/frig.h"
#include "depth_cloud.h"
#include "synth_truth.h"

/* Weights of a rig's shapes from (name, weight) pairs. */
static void rig_weights(const frig_rig *rig, int n, char (*names)[64], const double *w, double *out) {
    memset(out, 0, sizeof(double) * (size_t)frig_rig_shape_count(rig));
    for (int k = 0; k < n; k++) {
        int j = frig_rig_shape_find(rig, names[k]);
        if (j >= 0) out[j] = w[k];
    }
}

/* Keep only the mask's pixels within 2 pixels of a point of 'like' (photo i's cloud and margin)
 * projected through the fitted pose and camera. */
static void restrict_to_cloud(const frig_clouds *like, size_t i, const double R[9], const double t[3],
                              const fr_camera *cam, int W, int H, unsigned char *mask) {
    size_t n = frig_clouds_count(like, i) + frig_clouds_margin_count(like, i);
    const float *x = frig_clouds_xyz(like, i);
    unsigned char *near = calloc((size_t)W * H, 1);
    double *uv = malloc(sizeof(double) * 2 * (n + 1));
    if (n) fr_project_points(cam, R, t, x, (int)n, uv, NULL);
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(uv[2 * k])) continue;
        int u = (int)lround(uv[2 * k]), v = (int)lround(uv[2 * k + 1]);
        for (int dy = -2; dy <= 2; dy++)
            for (int dx = -2; dx <= 2; dx++)
                if (u + dx >= 0 && u + dx < W && v + dy >= 0 && v + dy < H) near[(size_t)(v + dy) * W + u + dx] = 1;
    }
    for (size_t k = 0; k < (size_t)W * H; k++) mask[k] &= near[k];
    free(near), free(uv);
}

static int cloud_of_photo(frig_ctx *ctx, const frig_photoset *set, size_t i, const frig_rig *rig, int ideal,
                          int stride, const frig_clouds *like, frig_clouds *clouds) {
    const char *path = frig_photoset_path(set, i);
    synth_photo_truth tr;
    if (!synth_truth_read(path, 1, &tr)) {
        fprintf(stderr, "%s: no synth truth beside it\n", path);
        return 0;
    }
    int W = tr.width, H = tr.height;
    double R[9], t[3], f;
    int persp;
    frig_photoset_fit_pose(set, i, R, t, &f, &persp);
    fr_camera cam_true = fr_camera_perspective(tr.f, W, H);
    cam_true.cx = tr.cx, cam_true.cy = tr.cy;
    fr_camera cam_fit = persp ? fr_camera_perspective(f, W, H) : fr_camera_weak(f, W, H);
    unsigned char *mask = NULL;
    int ns = frig_rig_shape_count(rig);
    double *w = calloc((size_t)ns + 1, sizeof(double));
    if (ideal) {
        /* The true rig beside the photos: subject_SS/rig/rig.frigrig. */
        char rig_path[4200];
        const char *slash = strrchr(path, '/');
        snprintf(rig_path, sizeof rig_path, "%.*srig/rig.frigrig", (int)(slash - 6 - path), path);
        frig_rig *truth = NULL;
        if (frig_rig_load(ctx, rig_path, &truth)) {
            fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
            free(w);
            synth_truth_free(&tr);
            return 0;
        }
        double *wt = calloc((size_t)frig_rig_shape_count(truth) + 1, sizeof(double));
        rig_weights(truth, tr.n_expr, tr.names, tr.weights, wt);
        mask = depth_cloud_face_mask(ctx, truth, wt, tr.R, tr.t, &cam_true, W, H);
        free(wt);
        frig_rig_free(truth);
    } else {
        int ne = frig_photoset_fit_expression_count(set);
        double *we = calloc((size_t)ne + 1, sizeof(double));
        frig_photoset_fit_expression(set, i, we);
        for (int k = 0; k < ne; k++) {
            int j = frig_rig_shape_find(rig, frig_photoset_fit_expression_name(set, k));
            if (j >= 0) w[j] = we[k];
        }
        free(we);
        mask = depth_cloud_face_mask(ctx, rig, w, R, t, &cam_fit, W, H);
    }
    free(w);
    if (mask && like) restrict_to_cloud(like, i, R, t, &cam_fit, W, H, mask);
    float *xyz = NULL, *nrm = NULL;
    long n = -1;
    if (mask && (ideal || !persp)) {
        n = depth_cloud_points(tr.depth, W, H, mask, tr.f, tr.cx, tr.cy, 0, 0, 1, tr.R, tr.t, stride, &xyz, &nrm);
    } else if (mask) {
        /* metres per pixel at the head's distance: fitted over true */
        double relief = (t[2] / f) / (tr.t[2] / tr.f);
        n = depth_cloud_points(tr.depth, W, H, mask, f, cam_fit.cx, cam_fit.cy, tr.t[2], t[2], relief, R, t, stride,
                               &xyz, &nrm);
    }
    float *conf = malloc(sizeof(float) * (n > 0 ? (size_t)n : 1));
    for (long k = 0; k < n; k++) conf[k] = 1.0f;
    int ok = n >= 0 && frig_clouds_set(ctx, clouds, i, (size_t)n, xyz, nrm, conf) == FRIG_OK;
    free(xyz), free(nrm), free(conf), free(mask);
    synth_truth_free(&tr);
    return ok;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: truth_clouds WORKSPACE [--ideal] [--stride N]\n");
        return 2;
    }
    const char *ws = argv[1];
    int ideal = 0, stride = 1, like_clouds = 0;
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "--ideal")) ideal = 1;
        else if (!strcmp(argv[i], "--stride") && i + 1 < argc) stride = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--like-clouds")) like_clouds = 1;
        else {
            fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    if (stride < 1) stride = 1;
    frig_ctx *ctx = frig_ctx_create();
    frig_photoset *set = NULL;
    frig_rig *rig = NULL;
    frig_clouds *clouds = NULL, *like = NULL;
    char path[4200];
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", ws);
    if (frig_photoset_load(ctx, ws, &set) || frig_rig_load(ctx, path, &rig) ||
        frig_clouds_create(ctx, frig_photoset_count(set), &clouds) ||
        (like_clouds && frig_clouds_load(ctx, set, ws, &like))) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    size_t made = 0, points = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        if (frig_photoset_status(set, i) != FRIG_PHOTO_OK || !frig_photoset_fitted(set, i)) continue;
        if ((!like || frig_clouds_count(like, i)) && cloud_of_photo(ctx, set, i, rig, ideal, stride, like, clouds)) made++, points += frig_clouds_count(clouds, i);
    }
    if (frig_clouds_save(ctx, clouds, set, ws)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    printf("%s: %zu clouds (%s), %zu points in all\n", ws, made, ideal ? "ideal: true pose and mask" : "fitted pose",
           points);
    frig_clouds_free(clouds);
    frig_clouds_free(like);
    frig_rig_free(rig);
    frig_photoset_free(set);
    frig_ctx_free(ctx);
    return 0;
}
