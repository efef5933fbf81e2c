/* Detect and fit on frig synth subjects, photo by photo (docs/fit.md, "Pose on synthetic
 * photos"): for a workspace made from one subject's photos (frig detect -> filter -> fit), the
 * subject face's landmarks against the truth's detector-like landmarks (mean px and mean over
 * the truth's outer-eye-corner distance, points 36-45, as NME) and the fitted head rotation
 * against the true one (degrees), with medians and means over the photos, split at |yaw| 30.
 * The photos are found through the workspace's report (.../subject_SS/photos/photo_PPP.jpg ->
 * .../subject_SS/truth/photo_PPP.json).
 * Usage: pose_eval WORKSPACE... [--photos] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frig/frig.h"
#include "raster/rotation.h"
#include "synth_truth.h"
#include "workspace/photoset.h"

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static double median(double *v, int n) {
    if (!n) return NAN;
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
static double mean(const double *v, int n) {
    double s = 0;
    for (int i = 0; i < n; i++) s += v[i];
    return n ? s / n : NAN;
}

typedef struct pool {
    double lm_px[4096], lm_nme[4096], rot[4096], rot_turned[4096], rot_frontal[4096];
    int n_lm, n_rot, n_turned, n_frontal, faces;
} pool;

static void pool_print(const char *name, pool *p) {
    double px = median(p->lm_px, p->n_lm), nme = median(p->lm_nme, p->n_lm);
    double mpx = mean(p->lm_px, p->n_lm), mnme = mean(p->lm_nme, p->n_lm);
    double mr = mean(p->rot, p->n_rot), mt = mean(p->rot_turned, p->n_turned), mf = mean(p->rot_frontal, p->n_frontal);
    printf("%-12s faces %3d detected %3d fitted %3d | landmarks median %6.2f px %6.2f%%  mean %6.2f px %6.2f%% | "
           "rotation median %6.2f mean %6.2f deg (|yaw|<30: %d, %.2f / %.2f; >=30: %d, %.2f / %.2f)\n",
           name, p->faces, p->n_lm, p->n_rot, px, 100 * nme, mpx, 100 * mnme, median(p->rot, p->n_rot), mr, p->n_frontal,
           median(p->rot_frontal, p->n_frontal), mf, p->n_turned, median(p->rot_turned, p->n_turned), mt);
}

static void pool_add(pool *all, const pool *p) {
    memcpy(all->lm_px + all->n_lm, p->lm_px, sizeof(double) * (size_t)p->n_lm);
    memcpy(all->lm_nme + all->n_lm, p->lm_nme, sizeof(double) * (size_t)p->n_lm);
    memcpy(all->rot + all->n_rot, p->rot, sizeof(double) * (size_t)p->n_rot);
    memcpy(all->rot_turned + all->n_turned, p->rot_turned, sizeof(double) * (size_t)p->n_turned);
    memcpy(all->rot_frontal + all->n_frontal, p->rot_frontal, sizeof(double) * (size_t)p->n_frontal);
    all->n_lm += p->n_lm, all->n_rot += p->n_rot, all->n_turned += p->n_turned, all->n_frontal += p->n_frontal;
    all->faces += p->faces;
}

static int evaluate(frig_ctx *ctx, const char *workspace, int per_photo, pool *p) {
    frig_photoset *set = NULL;
    if (frig_photoset_load(ctx, workspace, &set)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    memset(p, 0, sizeof *p);
    for (size_t i = 0; i < set->count && i < 4096; i++) {
        const fr_photo *ph = &set->photos[i];
        synth_photo_truth t;
        if (!synth_truth_read(ph->path, 0, &t) || !t.has_landmarks) continue;
        const double *lm = t.landmarks;
        p->faces++;
        double px = NAN, nme = NAN, rot = NAN;
        int src = -1;
        if (ph->subject >= 0 && ph->faces[ph->subject].has_landmarks) {
            const fr_face *f = &ph->faces[ph->subject];
            src = f->source;
            double s = 0, eye = hypot(lm[72] - lm[90], lm[73] - lm[91]);
            for (int k = 0; k < 68; k++) s += hypot(f->landmarks[2 * k] - lm[2 * k], f->landmarks[2 * k + 1] - lm[2 * k + 1]);
            px = s / 68, nme = px / eye;
            p->lm_px[p->n_lm] = px, p->lm_nme[p->n_lm++] = nme;
        }
        if (ph->fitted && ph->status == FRIG_PHOTO_OK) {
            rot = fr_rotation_angle_deg(ph->fit_rotation, t.R);
            p->rot[p->n_rot++] = rot;
            if (fabs(t.yaw_deg) >= 30) p->rot_turned[p->n_turned++] = rot;
            else p->rot_frontal[p->n_frontal++] = rot;
        }
        if (per_photo) {
            const char *name = strrchr(ph->path, '/');
            printf("  %-16s %-12s yaw %6.1f %-14s src %2d landmarks %7.2f px %6.2f%% rotation %6.2f\n",
                   name ? name + 1 : ph->path, t.failure, t.yaw_deg, frig_photo_status_name(ph->status), src, px, 100 * nme, rot);
        }
    }
    frig_photoset_free(set);
    return 0;
}

int main(int argc, char **argv) {
    int per_photo = 0, n = 0;
    const char *dirs[64];
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--photos")) per_photo = 1;
        else if (n < 64) dirs[n++] = argv[i];
    }
    if (n < 1) {
        fprintf(stderr, "usage: pose_eval WORKSPACE... [--photos]\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    static pool p, all;
    for (int k = 0; k < n; k++) {
        if (evaluate(ctx, dirs[k], per_photo, &p)) return 1;
        const char *name = strrchr(dirs[k], '/');
        pool_print(name ? name + 1 : dirs[k], &p);
        pool_add(&all, &p);
    }
    if (n > 1) pool_print("all", &all);
    frig_ctx_free(ctx);
    return 0;
}
