/* Benchmark of the model: ICT-FaceKit import, model file save and load, eval, glTF export.
 * Prints the median of several runs of each (seconds) and the model file's size.
 *   bench/model_load.sh [ICT_DIR]  builds and runs it against build/libfrig.so */
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <time.h>

#include <frig/frig.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int main(int argc, char **argv) {
    const char *ict = argc > 1 ? argv[1] : "../shared/ict-facekit";
    const char *file = argc > 2 ? argv[2] : "/tmp/frig-bench.frigmodel";
    frig_ctx *ctx = frig_ctx_create();
    frig_model *m = NULL;
    double t[9];
    for (int i = 0; i < 3; i++) {
        frig_model_free(m);
        double t0 = now();
        if (frig_model_import_ict(ctx, ict, &m)) {
            fprintf(stderr, "import failed: %s\n", frig_ctx_errmsg(ctx));
            return 1;
        }
        t[i] = now() - t0;
    }
    printf("import  (median of 3): %.3f s\n", median(t, 3));
    for (int i = 0; i < 3; i++) {
        double t0 = now();
        if (frig_model_save(ctx, m, file)) return 1;
        t[i] = now() - t0;
    }
    printf("save    (median of 3): %.3f s\n", median(t, 3));
    struct stat st;
    stat(file, &st);
    printf("model file: %lld bytes (%.1f MB)\n", (long long)st.st_size, st.st_size / 1e6);
    for (int i = 0; i < 9; i++) {
        frig_model *l = NULL;
        double t0 = now();
        if (frig_model_load(ctx, file, &l)) return 1;
        t[i] = now() - t0;
        frig_model_free(l);
    }
    printf("load    (median of 9): %.4f s\n", median(t, 9));
    double w[100] = {1, -1, 0.5};
    float *x = malloc(sizeof *x * 3 * (size_t)frig_model_vertex_count(m));
    for (int i = 0; i < 9; i++) {
        double t0 = now();
        frig_model_eval(ctx, m, w, NULL, x);
        t[i] = now() - t0;
    }
    printf("eval    (median of 9): %.5f s (100 identity modes)\n", median(t, 9));
    frig_rig *r = NULL;
    frig_rig_from_model(ctx, m, w, &r);
    for (int i = 0; i < 3; i++) {
        double t0 = now();
        if (frig_rig_save_gltf(ctx, r, "/tmp/frig-bench.glb")) return 1;
        t[i] = now() - t0;
    }
    printf("glb     (median of 3): %.3f s\n", median(t, 3));
    remove(file);
    remove("/tmp/frig-bench.glb");
    free(x);
    frig_rig_free(r);
    frig_model_free(m);
    frig_ctx_free(ctx);
    return 0;
}
