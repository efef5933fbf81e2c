/* The ICT-FaceKit importer and the model file: counts and correspondences against the
 * README and vertex_indices.json, shapes against a strtod reading of the OBJ files, the
 * upstream folder layout, edited folders failing with the file's name, save/load byte
 * identity, and evaluation against a per-vertex sum. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cblas.h>

#include "core/context.h"
#include "model/model.h"
#include "model/obj_reader.h"
#include "model_fixture.h"
#include "testing.h"

static double seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* Reference reading of an OBJ's 'v' lines with strtod, in centimetres. */
static double *ref_vertices(const char *dir, const char *name, int *count) {
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "r");
    if (!fp) return NULL;
    double *v = malloc(sizeof *v * 3 * 30000);
    char line[512];
    int n = 0;
    while (fgets(line, sizeof line, fp) && n < 30000)
        if (line[0] == 'v' && line[1] == ' ') {
            char *p = line + 2;
            for (int d = 0; d < 3; d++) v[3 * n + d] = strtod(p, &p);
            n++;
        }
    fclose(fp);
    *count = n;
    return v;
}

static void test_counts(const frig_model *m) {
    CHECK(frig_model_vertex_count(m) == 26719);
    CHECK(frig_model_polygon_count(m) == 26384);
    CHECK(frig_model_triangle_count(m) == 25836 * 2 + 548); /* 25836 quads, 548 triangles */
    CHECK(frig_model_uv_count(m) == 28911);
    CHECK(frig_model_identity_count(m) == 100);
    CHECK(frig_model_expression_count(m) == 57);
    CHECK(frig_model_material_count(m) == 12);
    CHECK(strcmp(frig_model_material_name(m, 0), "M_Face") == 0);
    const int32_t *lm = frig_model_landmarks(m);
    CHECK(lm[0] == 1225 && lm[8] == 966 && lm[30] == 4857 && lm[67] == 5966);
    const int32_t *v;
    CHECK(frig_model_rigid_vertices(m, &v) == 1487 && v[0] == 8786);
    int nfit = 0;
    for (int k = 0; k < 57; k++) nfit += frig_model_expression_fitting(m, k);
    CHECK(nfit == 53);
    CHECK(strcmp(frig_model_expression_name(m, 0), "browDown_L") == 0);
    CHECK(frig_model_expression_find(m, "cheekRaiser_L") == 53 && !frig_model_expression_fitting(m, 53));
    CHECK(frig_model_expression_find(m, "PupilDilate_R") == 56);
    CHECK(frig_model_expression_fitting(m, frig_model_expression_find(m, "jawOpen")));
    CHECK(frig_model_expression_find(m, "tongueOut") == -1);
    /* Polygon offsets: 25836 quads + 548 triangles. */
    CHECK(frig_model_polygon_offsets(m)[26384] == 25836 * 4 + 548 * 3);
}

static void test_regions(const frig_model *m) {
    const char *name;
    int first, count;
    CHECK(frig_model_region_count(m) == 22);
    CHECK(frig_model_region(m, frig_model_region_find(m, "face"), &name, &first, &count) == FRIG_OK);
    CHECK(first == 0 && count == 9409);
    frig_model_region(m, frig_model_region_find(m, "narrow_face"), NULL, &first, &count);
    CHECK(first == 0 && count == 6706);
    frig_model_region(m, frig_model_region_find(m, "teeth"), NULL, &first, &count);
    CHECK(first == 17039 && count == 4412);
    frig_model_region(m, frig_model_region_find(m, "eyelashes_right"), NULL, &first, &count);
    CHECK(first == 26035 && first + count == 26719);
    CHECK(frig_model_region_find(m, "nose") == -1);
    CHECK(frig_model_region(m, 99, &name, &first, &count) == FRIG_ERR_INVALID_ARGUMENT);
}

/* Contours run from the ear (high, far from the middle) down to the chin. */
static void test_contours(const frig_model *m) {
    const float *x = frig_model_neutral(m);
    for (int side = 0; side < 2; side++) {
        const int32_t *v;
        int n = frig_model_contour(m, side, &v);
        CHECK(n == 17);
        CHECK(x[3 * v[0] + 1] > x[3 * v[n - 1] + 1] + 0.10);           /* 11.7 cm higher */
        CHECK(fabs(x[3 * v[0]]) > fabs(x[3 * v[n - 1]]) + 0.05);         /* further out */
        CHECK(side == 0 ? x[3 * v[0]] < 0 : x[3 * v[0]] > 0);            /* subject's right = -x */
    }
    const int32_t *r, *l;
    frig_model_contour(m, 0, &r);
    frig_model_contour(m, 1, &l);
    CHECK(r[0] == 1280 && r[16] == 800 && l[0] == 3498 && l[16] == 3041);
    CHECK(frig_model_contour(m, 2, &r) == 0 && r == NULL);
}

/* Neutral and deltas against an independent reading of the OBJ files (cm -> m). */
static void test_shapes(const frig_model *m, const char *dir) {
    int n0, n1, n2;
    double *neutral = ref_vertices(dir, "generic_neutral_mesh.obj", &n0);
    double *jaw = ref_vertices(dir, "jawOpen.obj", &n1);
    double *id = ref_vertices(dir, "identity057.obj", &n2);
    CHECK(neutral && jaw && id && n0 == 26719 && n1 == 26719 && n2 == 26719);
    if (!neutral || !jaw || !id) return;
    const float *x = frig_model_neutral(m);
    size_t n3 = 3 * 26719;
    const float *dj = frig_model_expression_deltas(m) + n3 * (size_t)frig_model_expression_find(m, "jawOpen");
    const float *di = frig_model_identity_modes(m) + n3 * 57;
    double e0 = 0, e1 = 0, e2 = 0, moved = 0;
    for (size_t i = 0; i < n3; i++) {
        e0 = fmax(e0, fabs(x[i] - neutral[i] / 100));
        e1 = fmax(e1, fabs(x[i] + dj[i] - jaw[i] / 100));
        e2 = fmax(e2, fabs(x[i] + di[i] - id[i] / 100));
        moved = fmax(moved, fabs(dj[i]));
    }
    printf("import vs strtod: neutral %.2g m, jawOpen %.2g m, identity057 %.2g m; jawOpen moves up to %.4f m\n", e0, e1,
           e2, moved);
    CHECK(e0 < 1e-7 && e1 < 1e-7 && e2 < 1e-7);
    CHECK(moved > 0.01); /* the jaw drops by centimetres: deltas are really in metres */
    free(neutral), free(jaw), free(id);
}

static void test_round_trip(frig_ctx *ctx, const frig_model *m, const char *tmp) {
    char a[4200], b[4200];
    snprintf(a, sizeof a, "%s/a.frigmodel", tmp);
    snprintf(b, sizeof b, "%s/b.frigmodel", tmp);
    frig_model *l = NULL;
    CHECK(frig_model_save(ctx, m, a) == FRIG_OK);
    CHECK(frig_model_load(ctx, a, &l) == FRIG_OK);
    CHECK(frig_model_save(ctx, l, b) == FRIG_OK);
    size_t na = 0, nb = 0;
    unsigned char *da = test_read_file(a, &na), *db = test_read_file(b, &nb);
    CHECK(da && db && na == nb && na > 50000000 && memcmp(da, db, na) == 0);
    CHECK(l && memcmp(frig_model_identity_modes(l), frig_model_identity_modes(m), sizeof(float) * 3 * 26719 * 100) == 0);
    printf("model file: %zu bytes, save -> load -> save byte-identical\n", na);
    free(da), free(db);
    frig_model_free(l);
    CHECK(frig_model_load(ctx, "/nonexistent/x.frigmodel", &l) == FRIG_ERR_NOT_FOUND && l == NULL);
}

/* frig_model_eval against sum_k w_k U_k per vertex, in double. */
static void test_eval(frig_ctx *ctx, const frig_model *m) {
    double wi[100], we[57];
    uint64_t s = 12345;
    for (int k = 0; k < 100; k++) s = s * 6364136223846793005ULL + 1442695040888963407ULL, wi[k] = ((double)(s >> 11) / 9007199254740992.0 - 0.5) * 4;
    for (int k = 0; k < 57; k++) s = s * 6364136223846793005ULL + 1442695040888963407ULL, we[k] = (double)(s >> 11) / 9007199254740992.0;
    size_t n3 = 3 * 26719;
    float *out = malloc(sizeof *out * n3);
    CHECK(frig_model_eval(ctx, m, wi, we, out) == FRIG_OK);
    const float *x = frig_model_neutral(m), *U = frig_model_identity_modes(m), *E = frig_model_expression_deltas(m);
    /* The sum mode by mode (each mode a contiguous block), in double. */
    double worst = 0, *ref = malloc(sizeof *ref * n3);
    for (size_t i = 0; i < n3; i++) ref[i] = x[i];
    for (int k = 0; k < 100; k++)
        for (size_t i = 0; i < n3; i++) ref[i] += wi[k] * U[n3 * (size_t)k + i];
    for (int k = 0; k < 57; k++)
        for (size_t i = 0; i < n3; i++) ref[i] += we[k] * E[n3 * (size_t)k + i];
    for (size_t i = 0; i < n3; i++) worst = fmax(worst, fabs(ref[i] - out[i]));
    free(ref);
    printf("eval vs per-vertex sum: max error %.3g m\n", worst);
    CHECK(worst < 2e-6);
    /* The same bytes whatever OpenBLAS's thread count. */
    float *one = malloc(sizeof *one * n3);
    int saved = openblas_get_num_threads();
    openblas_set_num_threads(1);
    CHECK(frig_model_eval(ctx, m, wi, we, one) == FRIG_OK);
    openblas_set_num_threads(4);
    CHECK(frig_model_eval(ctx, m, wi, we, out) == FRIG_OK && memcmp(out, one, sizeof *out * n3) == 0);
    openblas_set_num_threads(saved);
    free(one);
    CHECK(frig_model_eval(ctx, m, NULL, NULL, out) == FRIG_OK && memcmp(out, x, sizeof *out * n3) == 0);
    wi[3] = NAN;
    CHECK(frig_model_eval(ctx, m, wi, NULL, out) == FRIG_ERR_INVALID_ARGUMENT);
    free(out);
}

static int run(const char *cmd) {
    int rc = system(cmd);
    if (rc != 0) fprintf(stderr, "command failed: %s\n", cmd);
    return rc;
}

/* A folder of symlinks to the ICT files, for edits. */
static const char *link_folder(const char *ict, const char *name) {
    const char *dir = test_temp_dir(name);
    char cmd[9000];
    snprintf(cmd, sizeof cmd, "ln -s '%s'/* '%s'/", ict, dir);
    run(cmd);
    return dir;
}

/* Upstream layout: every file repeats the neutral's vt/usemtl/f lines after its v lines. */
static void make_upstream(const char *ict, const char *dir, const char *name) {
    char cmd[9000];
    snprintf(cmd, sizeof cmd,
             "rm -f '%s/%s' && { grep '^v ' '%s/%s'; grep -E '^(vt|usemtl|f) ' '%s/generic_neutral_mesh.obj'; } > '%s/%s'",
             dir, name, ict, name, ict, dir, name);
    run(cmd);
}

static void expect_failure(frig_ctx *ctx, const char *dir, frig_status want, const char *needle1, const char *needle2) {
    frig_model *m = NULL;
    frig_status s = frig_model_import_ict(ctx, dir, &m);
    printf("edited folder: [%s] %s\n", frig_strerror(s), frig_ctx_errmsg(ctx));
    CHECK(s == want && m == NULL);
    CHECK(strstr(frig_ctx_errmsg(ctx), needle1) != NULL);
    if (needle2) CHECK(strstr(frig_ctx_errmsg(ctx), needle2) != NULL);
    frig_model_free(m);
}

static void test_upstream_and_edits(frig_ctx *ctx, const char *ict, const frig_model *ref) {
    const char *up = link_folder(ict, "model_upstream");
    make_upstream(ict, up, "identity000.obj");
    make_upstream(ict, up, "jawOpen.obj");
    make_upstream(ict, up, "PupilDilate_L.obj");
    frig_model *m = NULL;
    CHECK(frig_model_import_ict(ctx, up, &m) == FRIG_OK);
    unsigned char *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    if (m) {
        CHECK(fr_model_pack(ctx, m, 100, 57, &a, &na) == FRIG_OK);
        CHECK(fr_model_pack(ctx, ref, 100, 57, &b, &nb) == FRIG_OK);
        CHECK(a && b && na == nb && memcmp(a, b, na) == 0);
        printf("upstream layout: same model bytes as the v-only layout\n");
    }
    free(a), free(b);
    frig_model_free(m);

    char cmd[9000];
    const char *dir = link_folder(ict, "model_missing");
    snprintf(cmd, sizeof cmd, "rm '%s/jawOpen.obj'", dir);
    run(cmd);
    expect_failure(ctx, dir, FRIG_ERR_NOT_FOUND, "jawOpen.obj", "missing");

    dir = link_folder(ict, "model_short");
    snprintf(cmd, sizeof cmd, "rm '%s/eyeBlink_L.obj' && sed '/^v /{x;s/^/x/;/^x$/{x;d};x}' '%s/eyeBlink_L.obj' > '%s/eyeBlink_L.obj'", dir, ict, dir);
    run(cmd);
    expect_failure(ctx, dir, FRIG_ERR_CORRUPT, "eyeBlink_L.obj", "26718 vertices");

    dir = link_folder(ict, "model_bad_number");
    snprintf(cmd, sizeof cmd, "rm '%s/identity042.obj' && sed '100s/^v \\([^ ]*\\) /v \\1x /' '%s/identity042.obj' > '%s/identity042.obj'",
             dir, ict, dir);
    run(cmd);
    expect_failure(ctx, dir, FRIG_ERR_CORRUPT, "identity042.obj line 100", "malformed number");

    dir = link_folder(ict, "model_other_faces");
    make_upstream(ict, dir, "mouthClose.obj");
    snprintf(cmd, sizeof cmd, "sed -i 's/^f 874\\/1 12\\/2 /f 12\\/2 874\\/1 /' '%s/mouthClose.obj'", dir);
    run(cmd);
    expect_failure(ctx, dir, FRIG_ERR_CORRUPT, "mouthClose.obj", "faces differ");

    expect_failure(ctx, "/nonexistent/ict", FRIG_ERR_NOT_FOUND, "/nonexistent/ict", NULL);
}

/* The hand-written number parser against strtod on numbers printed to 9 digits. */
static void test_number_parser(void) {
    const char *fixed[] = {"0", "-0", "1", "-2.5", "1e-08", "-3.17186e-08", "11.7028", "+7.", ".5", "6.02214076e23", "1E+2"};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) {
        const char *p = fixed[i];
        double v;
        CHECK(fr_parse_double(&p, fixed[i] + strlen(fixed[i]), &v) && v == strtod(fixed[i], NULL) && *p == 0);
    }
    const char *bad[] = {"", "-", ".", "e5", "1e", "nan", "inf"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const char *p = bad[i];
        double v;
        CHECK(!fr_parse_double(&p, bad[i] + strlen(bad[i]), &v));
    }
    uint64_t s = 99;
    int mismatches = 0;
    for (int i = 0; i < 20000; i++) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        double x = ((double)(s >> 11) / 9007199254740992.0 - 0.5) * pow(10, (int)(s % 17) - 8);
        char buf[64];
        snprintf(buf, sizeof buf, "%.9g", x);
        const char *p = buf;
        double v = 0;
        if (!fr_parse_double(&p, buf + strlen(buf), &v) || v != strtod(buf, NULL)) mismatches++;
    }
    CHECK(mismatches == 0);
}

static void test_default_path(frig_ctx *ctx) {
    char buf[512];
    setenv("FRIG_MODEL", "/x/y.frigmodel", 1);
    CHECK(frig_model_default_path(ctx, buf, sizeof buf) == FRIG_OK && strcmp(buf, "/x/y.frigmodel") == 0);
    unsetenv("FRIG_MODEL");
    setenv("XDG_DATA_HOME", "/data", 1);
    CHECK(frig_model_default_path(ctx, buf, sizeof buf) == FRIG_OK && strcmp(buf, "/data/frig/ict.frigmodel") == 0);
    unsetenv("XDG_DATA_HOME");
    setenv("HOME", "/home/u", 1);
    CHECK(frig_model_default_path(ctx, buf, sizeof buf) == FRIG_OK &&
          strcmp(buf, "/home/u/.local/share/frig/ict.frigmodel") == 0);
    CHECK(frig_model_default_path(ctx, buf, 8) == FRIG_ERR_INVALID_ARGUMENT);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_number_parser();
    const char *ict = fixture_ict_dir();
    if (!ict) {
        frig_ctx_free(ctx);
        return test_skip("the ICT-FaceKit folder (../shared/ict-facekit) is missing");
    }
    double t0 = seconds();
    frig_model *m = NULL;
    CHECK(frig_model_import_ict(ctx, ict, &m) == FRIG_OK);
    printf("import of %s: %.2f s (%s)\n", ict, seconds() - t0, frig_ctx_errmsg(ctx));
    if (m) {
        /* Refresh the cache the other tests use. */
        if (system("mkdir -p '" FRIG_BINARY_DIR "/test-tmp/model-cache'") == 0) frig_model_save(ctx, m, fixture_model_path());
        test_counts(m);
        test_regions(m);
        test_contours(m);
        test_shapes(m, ict);
        test_round_trip(ctx, m, test_temp_dir("model_round_trip"));
        test_eval(ctx, m);
        test_upstream_and_edits(ctx, ict, m);
    }
    test_default_path(ctx);
    frig_model_free(m);
    frig_ctx_free(ctx);
    return test_result("test_model");
}
