/* The held-out check of the sfs stage on frig synth subjects (issue 10's bar), from the files a
 * workspace holds: for each subject's workspace (detect -> filter -> fit -> sfs run on its
 * photos), the clouds WORKSPACE/clouds/<stem>.ply scored against the true posed surface (the
 * true rig at the photo's true expression, head frame, face material) after a similarity
 * alignment (ICP with Umeyama's solution per round); per photo the mean, median and p90 point
 * distance; per subject the median over photos of the mean distance, the share of the photos
 * showing a face that have a cloud, and the clouds made from photos that show no face or are
 * under- or over-exposed. Bar: median <= 1.0 mm, share >= 70%, at most one such cloud.
 * --bands also prints the mean distance by height band of the aligned points (chin and neck, mouth and
 * nose, eyes, forehead) and each band's share of the points.
 * --normals prints the mean distance by the direction the aligned points' normals face (down, down-ish,
 * forward, sideways, up); --min-confidence C scores only the points whose confidence is at least C
 * (how much a stricter region selection would change).
 * Usage: sfs_holdout SUBJECT_DIR WORKSPACE [SUBJECT_DIR WORKSPACE]... [--verbose] [--bands] [--normals]
 *        [--min-confidence C] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "eval/cloud_error.h"
#include "frig/frig.h"
#include "sfs/sfs.h"
#include "sfs_truth.h"

static int cmp_d(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* --bands: the aligned points' distances by height in the head frame (the bands of
 * retarget_eval --where: chin and neck, mouth and nose, eyes, forehead), summed over photos. */
#define N_BANDS 4
static const double band_top[N_BANDS] = {-0.0316, 0.0062, 0.0358, 1e9};
typedef struct band_sum {
    double sum[N_BANDS];
    size_t count[N_BANDS];
} band_sum;

static void band_add(const double *pts, const double *d, size_t n, double s, const double R[9], const double t[3],
                     band_sum *b) {
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(d[k])) continue;
        const double *x = pts + 3 * k;
        double y = s * (R[3] * x[0] + R[4] * x[1] + R[5] * x[2]) + t[1];
        int q = 0;
        while (q < N_BANDS - 1 && y > band_top[q]) q++;
        b->sum[q] += d[k], b->count[q]++;
    }
}

static double min_conf = 0;
static int by_normal = 0;
/* --normals: the aligned points' distances by the direction their normal faces (up, forward, down...) */
static double nsum[5];
static size_t ncount[5];
static void normal_add(const float *nrm, const double *d, size_t n, const double R[9]) {
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(d[k])) continue;
        const float *v = nrm + 3 * k;
        double y = R[3] * v[0] + R[4] * v[1] + R[5] * v[2], z = R[6] * v[0] + R[7] * v[1] + R[8] * v[2];
        int q = y < -0.6 ? 0 : y < -0.3 ? 1 : z > 0.8 ? 2 : y < 0.3 ? 3 : 4;
        nsum[q] += d[k], ncount[q]++;
    }
}

static int score_subject(frig_ctx *ctx, const char *subject_dir, const char *ws, int verbose, double *median,
                         int *faces, int *with, int *bad, int *photos, band_sum *bands) {
    char path[4096];
    frig_rig *truth = NULL;
    frig_photoset *set = NULL;
    frig_clouds *clouds = NULL;
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", subject_dir);
    if (frig_rig_load(ctx, path, &truth) || frig_photoset_load(ctx, ws, &set) ||
        frig_clouds_load(ctx, set, ws, &clouds)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    fr_sfs_mesh m;
    if (fr_sfs_mesh_init(ctx, truth, &m)) return 1;
    int32_t *ftris = malloc(sizeof(int32_t) * 3 * (size_t)m.nt);
    int nft = 0;
    for (int t = 0; t < m.nt; t++)
        if (m.face[t]) memcpy(ftris + 3 * nft++, m.tris + 3 * t, sizeof(int32_t) * 3);
    float *xyz = malloc(sizeof(float) * 3 * (size_t)m.nv);
    double *means = malloc(sizeof(double) * (frig_photoset_count(set) + 1));
    int nm = 0;
    *faces = *with = *bad = *photos = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        const char *photo = frig_photoset_path(set, i);
        bench_truth tr;
        if (!bench_truth_load(photo, truth, &tr)) continue;
        (*photos)++;
        size_t n = frig_clouds_count(clouds, i);
        int exposure = !strcmp(tr.failure, "underexposed") || !strcmp(tr.failure, "overexposed");
        if (tr.has_face) (*faces)++;
        if (n && tr.has_face) (*with)++;
        if (n && (!tr.has_face || exposure)) (*bad)++;
        const char *base = strrchr(photo, '/');
        base = base ? base + 1 : photo;
        if (!n || !tr.has_face) {
            if (verbose)
                printf("  %-14s %-12s %-14s %s\n", base, tr.failure, frig_photo_status_name(frig_photoset_status(set, i)),
                       n ? "CLOUD FROM A PHOTO WITHOUT A FACE" : "");
            bench_truth_free(&tr);
            continue;
        }
        fr_sfs_mesh_eval(&m, tr.weights, xyz);
        fr_tri_tree *ix = NULL;
        fr_tri_tree_build(ctx, xyz, ftris, nft, &ix);
        const float *p = frig_clouds_xyz(clouds, i), *conf = frig_clouds_confidence(clouds, i);
        double *pts = malloc(sizeof(double) * 3 * n), *d = malloc(sizeof(double) * n), s, R[9], t[3];
        const float *nr = frig_clouds_normals(clouds, i);
        float *nk = malloc(sizeof(float) * 3 * n + 1);
        size_t kept = 0;
        for (size_t k = 0; k < n; k++)
            if (conf[k] >= min_conf) {
                for (int c = 0; c < 3; c++) pts[3 * kept + c] = p[3 * k + c], nk[3 * kept + c] = nr[3 * k + c];
                kept++;
            }
        n = kept;
        fr_cloud_align(ctx, ix, pts, (int)n, 15, 0.01, d, &s, R, t);
        if (bands) band_add(pts, d, n, s, R, t, bands);
        if (by_normal) normal_add(nk, d, n, R);
        free(nk);
        int finite = 0;
        for (size_t k = 0; k < n; k++)
            if (isfinite(d[k])) d[finite++] = d[k];
        double mean, med, p90;
        fr_error_stats(d, finite, &mean, &med, &p90);
        means[nm++] = mean;
        if (verbose)
            printf("  %-14s %-12s %-14s %6zu points: mean %.3f, median %.3f, p90 %.3f mm%s\n", base, tr.failure,
                   frig_photo_status_name(frig_photoset_status(set, i)), n, 1e3 * mean, 1e3 * med, 1e3 * p90,
                   exposure ? "  (EXPOSURE FAILURE)" : "");
        free(pts), free(d);
        fr_tri_tree_free(ix);
        bench_truth_free(&tr);
    }
    qsort(means, (size_t)nm, sizeof *means, cmp_d);
    *median = nm ? (nm % 2 ? means[nm / 2] : 0.5 * (means[nm / 2 - 1] + means[nm / 2])) : NAN;
    free(means), free(xyz), free(ftris);
    fr_sfs_mesh_free(&m);
    frig_clouds_free(clouds), frig_photoset_free(set), frig_rig_free(truth);
    return 0;
}

int main(int argc, char **argv) {
    int verbose = 0, pairs = 0, pass = 1, by_band = 0;
    const char *args[512];
    for (int i = 1; i < argc && pairs < 512; i++) {
        if (!strcmp(argv[i], "--verbose")) verbose = 1;
        else if (!strcmp(argv[i], "--bands")) by_band = 1;
        else if (!strcmp(argv[i], "--normals")) by_normal = 1;
        else if (!strcmp(argv[i], "--min-confidence") && i + 1 < argc) min_conf = atof(argv[++i]);
        else args[pairs++] = argv[i];
    }
    if (pairs < 2 || pairs % 2) {
        fprintf(stderr, "usage: sfs_holdout SUBJECT_DIR WORKSPACE [SUBJECT_DIR WORKSPACE]... [--verbose] [--bands] [--normals] "
                        "[--min-confidence C]\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    printf("%-28s %7s %8s %8s %10s %s\n", "subject", "photos", "faces", "clouds", "median mm", "bar");
    for (int k = 0; k < pairs; k += 2) {
        double med;
        int faces, with, bad, photos;
        if (verbose) printf("%s:\n", args[k]);
        band_sum bs;
        memset(&bs, 0, sizeof bs);
        if (score_subject(ctx, args[k], args[k + 1], verbose, &med, &faces, &with, &bad, &photos, by_band ? &bs : NULL))
            return 1;
        double share = faces ? (double)with / faces : 0;
        int ok = 1e3 * med <= 1.0 && share >= 0.7 && bad <= 1;
        pass &= ok;
        printf("%-28s %7d %8d %4d %3.0f%% %10.3f %s (clouds from no-face/exposure photos: %d)\n", args[k], photos, faces,
               with, 100 * share, 1e3 * med, ok ? "pass" : "FAIL", bad);
        if (by_band) {
            size_t all = 0;
            for (int q = 0; q < N_BANDS; q++) all += bs.count[q];
            printf("  by height (chin..top), mean mm (share of points):");
            for (int q = 0; q < N_BANDS; q++)
                printf(" %.3f (%.0f%%)", bs.count[q] ? 1e3 * bs.sum[q] / bs.count[q] : NAN,
                       all ? 100.0 * bs.count[q] / all : 0.0);
            printf("\n");
        }
    }
    if (by_normal) {
        static const char *name[5] = {"down", "down-ish", "forward", "sideways", "up"};
        printf("by the normal's direction, mean mm (points):");
        for (int q = 0; q < 5; q++) printf(" %s %.3f (%zu)", name[q], ncount[q] ? 1e3 * nsum[q] / ncount[q] : NAN, ncount[q]);
        printf("\n");
    }
    printf("all subjects: %s\n", pass ? "pass" : "FAIL");
    frig_ctx_free(ctx);
    return 0;
}
