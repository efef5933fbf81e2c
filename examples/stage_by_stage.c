/* The pipeline through libfrig's public API, one stage at a time: what `frig run` does, without
 * its resuming, video frames and report page: detect, filter, fit, sfs (a point cloud per photo
 * from its shading, the albedo), retarget with the outer loop (refit on the new rig, sfs again,
 * retarget: retarget.iterations rounds), export.
 *
 *   stage_by_stage MODEL OUT PHOTO...
 *
 * MODEL is the model file `frig model import-ict` writes; the detector's data come from Debian
 * (opencv-data, libdlib-data). Writes OUT/rig.glb (the personalized rig, its face textured with
 * OUT/albedo.png) and OUT/shapes/ and prints what each stage did.
 * Build against an installed libfrig:
 *   cc -std=c11 stage_by_stage.c $(pkg-config --cflags --libs frig) -o stage_by_stage */
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <frig/frig.h>

static int fail(frig_ctx *ctx, const char *what) {
    fprintf(stderr, "stage_by_stage: %s: %s\n", what, frig_ctx_errmsg(ctx));
    return 1;
}

static size_t count_status(const frig_photoset *set, frig_photo_status status) {
    size_t n = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++) n += frig_photoset_status(set, i) == status;
    return n;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: stage_by_stage MODEL OUT PHOTO...\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    frig_model *model = NULL;
    frig_photoset *set = NULL;
    frig_detector *det = NULL;
    frig_rig *rig = NULL;
    frig_clouds *clouds = NULL;
    frig_image *albedo = NULL;
    int rc = 1;
    if (!ctx) return 1;
    if (frig_model_load(ctx, argv[1], &model)) {
        fail(ctx, "model");
        goto done;
    }
    /* the photos */
    if (frig_photoset_create(ctx, &set)) goto done;
    for (int i = 3; i < argc; i++)
        if (frig_photoset_add(ctx, set, argv[i], NULL)) {
            fail(ctx, argv[i]);
            goto done;
        }
    /* detect: faces and 68 landmarks (paper section 4.2) */
    if (frig_detector_create(ctx, NULL, NULL, &det) || frig_detect_photoset(ctx, det, set)) {
        fail(ctx, "detect");
        goto done;
    }
    printf("detect: %zu photos, %zu with a usable face\n", frig_photoset_count(set), count_status(set, FRIG_PHOTO_OK));
    /* filter: failed detections out (Algorithm 1) */
    if (frig_filter(ctx, set, NULL)) {
        fail(ctx, "filter");
        goto done;
    }
    printf("filter: %zu outliers dropped, %zu photos left\n", count_status(set, FRIG_PHOTO_OUTLIER),
           count_status(set, FRIG_PHOTO_OK));
    /* fit: camera, pose and expression per photo, one identity (sections 4.3-4.4) */
    if (frig_fit(ctx, model, set)) {
        fail(ctx, "fit");
        goto done;
    }
    size_t fitted = 0;
    double sum = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++)
        if (frig_photoset_fitted(set, i) && frig_photoset_status(set, i) == FRIG_PHOTO_OK)
            fitted++, sum += frig_photoset_fit_error(set, i);
    printf("fit: %zu photos, mean landmark error %.2f px\n", fitted, fitted ? sum / (double)fitted : 0.0);
    /* the model-space rig of the fitted identity: where sfs and retarget start */
    const double *identity = NULL;
    frig_photoset_identity(set, &identity);
    if (frig_rig_from_model(ctx, model, identity, &rig)) {
        fail(ctx, "rig");
        goto done;
    }
    /* sfs: a point cloud per photo from its shading, the subject's albedo (section 5.1); with the
     * model its identity modes are solved with the shape all photos share (sfs.identity_modes) */
    if (frig_sfs_with_model(ctx, model, rig, set, NULL, &clouds, &albedo)) {
        fail(ctx, "sfs");
        goto done;
    }
    size_t with = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++) with += frig_clouds_count(clouds, i) > 0;
    printf("sfs: %zu point clouds, %zu photos sfs_failed\n", with, count_status(set, FRIG_PHOTO_SFS_FAILED));
    /* retarget: the personalized rig, beyond the model's span, with the outer loop (sections 5.2-5.3) */
    if (frig_retarget_refine(ctx, model, set, &clouds, rig, frig_retarget_recover_sfs, &albedo)) {
        fail(ctx, "retarget");
        goto done;
    }
    int rounds = frig_photoset_retarget_rounds(set), photos = 0;
    double moved = 0, rms = 0;
    if (rounds > 0) frig_photoset_retarget_round(set, rounds - 1, &moved, &photos, &rms);
    printf("retarget: %d rounds, %d photos, the last moved the neutral %.3f mm, cloud RMS %.2f mm\n", rounds, photos,
           moved, rms);
    /* export: the personalized rig, its face textured with the albedo */
    char glb[4096], shapes[4096], texture[4096];
    snprintf(glb, sizeof glb, "%s/rig.glb", argv[2]);
    snprintf(shapes, sizeof shapes, "%s/shapes", argv[2]);
    snprintf(texture, sizeof texture, "%s/albedo.png", argv[2]);
    mkdir(argv[2], 0755); /* POSIX; an existing folder is fine */
    if (frig_image_save_png(ctx, albedo, texture) || frig_rig_set_face_texture(ctx, rig, texture) ||
        frig_rig_save_obj(ctx, rig, shapes) || frig_rig_save_gltf(ctx, rig, glb)) {
        fail(ctx, "export");
        goto done;
    }
    printf("export: %s and %s/ (%d blendshapes)\n", glb, shapes, frig_rig_target_count(rig));
    rc = 0;
done:
    frig_image_free(albedo);
    frig_clouds_free(clouds);
    frig_rig_free(rig);
    frig_detector_free(det);
    frig_photoset_free(set);
    frig_model_free(model);
    frig_ctx_free(ctx);
    return rc;
}
