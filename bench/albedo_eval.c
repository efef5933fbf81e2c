/* The sfs stage's albedo texture (textures/albedo.png, docs/sfs.md) against a frig synth
 * subject's true albedo (lib/eval/albedo_error.h): the subject made again from its seed (with the
 * --set options it was made with; its neutral is compared with the true rig's to say so). Prints
 * the error's mean, 90th and 99th percentiles (colour distance over the skin's brightness) and
 * the share of vertices over 0.5 (a colour that is not the skin's: the outline's tints).
 * With WORKSPACE "-": the true albedo itself baked into the texture's layout (what the measure
 * gives a perfect texture: its floor, from the texels' sRGB steps and the bake's interpolation).
 * --write PNG saves the texture it scored (with "-": the true albedo baked, to compare by eye).
 * Usage: albedo_eval SUBJECT_DIR WORKSPACE|- MODEL [--set NAME=VALUE ...] [--write PNG] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "bench_param.h"
#include "frig/frig.h"
#include "frig/synth.h"
#include "eval/albedo_error.h"
#include "image/image.h"
#include "image/srgb.h"
#include "rig/rig.h"
#include "sfs/sfs_uv.h"
#include "synth/synth.h"
#include "synth_truth.h"

static int read_seed(const char *subject_dir, uint64_t *seed) {
    char path[4200];
    snprintf(path, sizeof path, "%s/subject.json", subject_dir);
    char *text = synth_read_text(path);
    cJSON *j = text ? cJSON_Parse(text) : NULL;
    const cJSON *s = cJSON_GetObjectItem(j, "seed");
    int ok = cJSON_IsString(s);
    if (ok) *seed = strtoull(s->valuestring, NULL, 16);
    cJSON_Delete(j);
    free(text);
    return ok;
}

/* The true albedo baked into a size x size texture of the face's UV layout (sfs_uv.h). */
static frig_image *bake_truth(frig_ctx *ctx, const frig_synth_subject *subj, int size) {
    fr_sfs_mesh m;
    fr_sfs_uv uv;
    if (fr_sfs_mesh_init(ctx, frig_synth_subject_rig(subj), &m)) return NULL;
    frig_image *img = NULL;
    if (!fr_sfs_uv_init(ctx, &m, size, &uv)) {
        img = fr_image_new(size, size, 3);
        for (int k = 0; img && k < uv.count; k++) {
            const int32_t *tri = m.tris + 3 * (size_t)uv.tri[k];
            const float *b = uv.bary + 3 * (size_t)k;
            for (int c = 0; c < 3; c++) {
                double lin = 0;
                for (int q = 0; q < 3; q++) lin += b[q] * subj->albedo[3 * (size_t)tri[q] + c];
                img->pixels[(size_t)(uv.texel[k] / size) * img->stride + 3 * (size_t)(uv.texel[k] % size) + c] =
                    (uint8_t)floor(255.0 * fr_linear_to_srgb(lin) + 0.5);
            }
        }
        fr_sfs_uv_free(&uv);
    }
    fr_sfs_mesh_free(&m);
    return img;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: albedo_eval SUBJECT_DIR WORKSPACE|- MODEL [--set NAME=VALUE ...] [--write PNG]\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    const char *write = NULL;
    for (int i = 4; i + 1 < argc; i += 2)
        if (!strcmp(argv[i], "--write")) write = argv[i + 1];
        else if (strcmp(argv[i], "--set") || bench_set_param(ctx, argv[i + 1])) {
            fprintf(stderr, "albedo_eval: bad option %s %s\n", argv[i], argv[i + 1]);
            return 2;
        }
    uint64_t seed;
    frig_model *model = NULL;
    frig_synth_subject *subj = NULL;
    frig_rig *truth = NULL;
    frig_image *img = NULL;
    char path[4200];
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", argv[1]);
    if (!read_seed(argv[1], &seed) || frig_model_load(ctx, argv[3], &model) ||
        frig_synth_subject_create(ctx, model, seed, &subj) || frig_rig_load(ctx, path, &truth)) {
        fprintf(stderr, "albedo_eval: %s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    snprintf(path, sizeof path, "%s/textures/albedo.png", argv[2]);
    if (!strcmp(argv[2], "-") ? !(img = bake_truth(ctx, subj, 512))
                              : frig_image_load(ctx, path, FRIG_LOAD_IGNORE_ORIENTATION, &img) ||
                                    frig_image_channels(img) != 3) {
        fprintf(stderr, "albedo_eval: %s: %s\n", path, frig_ctx_errmsg(ctx));
        return 1;
    }
    /* the subject made again is the one on disk */
    const float *a = frig_rig_neutral(subj->rig), *b = frig_rig_neutral(truth);
    double worst = 0;
    for (int q = 0; q < 3 * subj->nv; q++) worst = fmax(worst, fabs((double)a[q] - b[q]));
    if (worst > 1e-6) {
        fprintf(stderr, "albedo_eval: the subject made from seed %016llx is not %s (neutral %.3g m off): "
                        "give the --set options it was made with\n",
                (unsigned long long)seed, argv[1], worst);
        return 1;
    }
    if (write && frig_image_save_png(ctx, img, write)) {
        fprintf(stderr, "albedo_eval: %s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    fr_albedo_error e;
    if (fr_albedo_error_of(ctx, subj, img, &e)) {
        fprintf(stderr, "albedo_eval: %s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    printf("albedo: %d face skin vertices, error mean %.3f p90 %.3f p99 %.3f, over %.1f: %.2f%% (scale %.2f %.2f %.2f)\n",
           e.vertices, e.mean, e.p90, e.p99, FR_ALBEDO_GROSS, 100.0 * e.gross, e.scale[0], e.scale[1], e.scale[2]);
    frig_image_free(img);
    frig_rig_free(truth);
    frig_synth_subject_free(subj);
    frig_model_free(model);
    frig_ctx_free(ctx);
    return 0;
}
