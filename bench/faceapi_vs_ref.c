/* Our C face networks against @vladmandic/face-api run by TensorFlow.js (the reference answers
 * in tests/data/faceapi_ref.jsonl, made by ../shared/tools/faceapi_ref.cjs): per photo, the
 * faces each finds, box IoU of matched faces (matched both ways), score, landmark and
 * descriptor differences end to end, each network on the reference's own input (the landmark
 * net on its box, the recognition net on its landmarks), and our time against the reference's.
 *   faceapi_vs_ref [--ref FILE] [--photos DIR] [--models DIR]
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/context.h"
#include "faceapi_ref.h"
#include "frig/frig.h"

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv) {
    const char *ref = FRIG_SOURCE_DIR "/tests/data/faceapi_ref.jsonl", *photos = FRIG_SOURCE_DIR "/../shared/photos";
    const char *models = NULL;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--ref")) ref = argv[i + 1];
        else if (!strcmp(argv[i], "--photos")) photos = argv[i + 1];
        else if (!strcmp(argv[i], "--models")) models = argv[i + 1];
    }
    frig_ctx *ctx = frig_ctx_create();
    fr_face_models *m = NULL;
    if (fr_face_models_load(ctx, models, &m)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    FILE *fp = fopen(ref, "r");
    if (!fp) {
        fprintf(stderr, "cannot read %s\n", ref);
        return 1;
    }
    int saved = fr_blas_serial_begin();
    static char line[1 << 22];
    static ref_image r;
    static ref_face ours[REF_MAX_FACES];
    int images = 0, ref_faces = 0, our_faces = 0, matched_both = 0, iou95 = 0, unmatched_ref = 0, unmatched_ours = 0;
    double sum_desc = 0, max_desc = 0, sum_score = 0, max_score = 0, sum_lm = 0, sum_iou = 0, min_iou = 1;
    double sum_lm_own = 0, sum_desc_own = 0, max_desc_own = 0;
    int desc_under = 0, desc_own_under = 0;
    double t_ours = 0, t_ref = 0;
    printf("%-56s %3s %4s %6s %8s %7s %8s %7s %8s %6s %7s\n", "photo", "ref", "ours", "minIoU", "dscore", "lm_px", "desc",
           "lm_own", "desc_own", "ms", "ref_ms");
    while (fgets(line, sizeof line, fp)) {
        if (!ref_parse_line(line, &r)) continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", photos, r.image);
        frig_image *img = NULL;
        double dl_own = 0, dd_own = 0;
        if (frig_image_load(ctx, path, FRIG_LOAD_IGNORE_ORIENTATION | FR_LOAD_LIKE_JPEG_JS, &img)) {
            printf("%-60s unreadable: %s\n", r.image, frig_ctx_errmsg(ctx));
            continue;
        }
        double t0 = now();
        int n = ours_run(ctx, m, img, ours, REF_MAX_FACES);
        double dt = now() - t0;
        fr_nn_image in = {img->pixels, img->stride, img->width, img->height, img->channels};
        for (int i = 0; i < r.n; i++) {
            double lm[136];
            int crop[4];
            float d[FR_FACE_DESCRIPTOR_SIZE];
            if (fr_landmark_net_run(ctx, m->landmarks, &in, r.faces[i].box, lm, crop) ||
                fr_recognition_net_run(ctx, m->recognition, &in, r.faces[i].landmarks, crop[2], crop[3], d))
                continue;
            double l = ref_landmark_distance(lm, r.faces[i].landmarks), e = fr_descriptor_distance(d, r.faces[i].descriptor);
            dl_own += l / r.n, dd_own += e / r.n;
            sum_lm_own += l, sum_desc_own += e, max_desc_own = fmax(max_desc_own, e), desc_own_under += e < 0.01;
        }
        frig_image_free(img);
        if (n < 0) {
            printf("%-60s failed: %s\n", r.image, frig_ctx_errmsg(ctx));
            continue;
        }
        ref_match mt;
        ref_match_faces(&r, ours, n, &mt);
        double mi = 1, ds = 0, dl = 0, dd = 0;
        int both = 0;
        for (int i = 0; i < r.n; i++) {
            int j = mt.match[i];
            if (j < 0 || mt.back[j] != i) {
                unmatched_ref++;
                continue;
            }
            both++;
            double s = fabs(r.faces[i].score - ours[j].score);
            double l = ref_landmark_distance(r.faces[i].landmarks, ours[j].landmarks);
            double d = fr_descriptor_distance(r.faces[i].descriptor, ours[j].descriptor);
            mi = fmin(mi, mt.iou[i]);
            ds = fmax(ds, s);
            dl += l;
            dd += d;
            sum_iou += mt.iou[i];
            min_iou = fmin(min_iou, mt.iou[i]);
            iou95 += mt.iou[i] >= 0.95;
            sum_score += s;
            max_score = fmax(max_score, s);
            sum_lm += l;
            sum_desc += d;
            max_desc = fmax(max_desc, d);
            desc_under += d < 0.01;
        }
        for (int j = 0; j < n; j++)
            if (mt.back[j] < 0 || mt.match[mt.back[j]] != j) unmatched_ours++;
        images++;
        ref_faces += r.n;
        our_faces += n;
        matched_both += both;
        t_ours += dt;
        t_ref += r.ms / 1000;
        printf("%-56s %3d %4d %6.3f %8.5f %7.3f %8.5f %7.3f %8.5f %6.0f %7.0f\n", r.image, r.n, n, both ? mi : 0.0, ds,
               both ? dl / both : 0.0, both ? dd / both : 0.0, dl_own, dd_own, dt * 1000, r.ms);
    }
    fclose(fp);
    fr_blas_serial_end(saved);
    printf("\nphotos %d; faces: reference %d, ours %d, matched both ways %d (unmatched: reference %d, ours %d)\n", images,
           ref_faces, our_faces, matched_both, unmatched_ref, unmatched_ours);
    if (matched_both)
        printf("matched faces: IoU mean %.4f min %.4f, >= 0.95: %d of %d; score |diff| mean %.2e max %.2e; landmarks "
               "mean %.4f px; descriptor distance mean %.5f max %.5f\n",
               sum_iou / matched_both, min_iou, iou95, matched_both, sum_score / matched_both, max_score,
               sum_lm / matched_both, sum_desc / matched_both, max_desc);
    if (matched_both)
        printf("faces with descriptor distance < 0.01: end to end %d of %d; on the reference's own landmarks %d of %d "
               "(mean %.5f, max %.5f; the landmark net on the reference's box: mean %.3f px)\n",
               desc_under, matched_both, desc_own_under, ref_faces, sum_desc_own / ref_faces, max_desc_own,
               sum_lm_own / ref_faces);
    printf("time: ours %.2f s, reference %.2f s (ratio %.4f), one thread\n", t_ours, t_ref, t_ref > 0 ? t_ours / t_ref : 0);
    fr_face_models_free(m);
    frig_ctx_free(ctx);
    return 0;
}
