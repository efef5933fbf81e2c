/* Point clouds: the handle, file names of photos that share a stem, the exact round trip
 * through WORKSPACE/clouds/, stale files removed, and every damaged PLY refused with a
 * status (no crash, nothing half-read). */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "frig/frig.h"
#include "testing.h"

static void write_bytes(const char *path, const void *data, size_t n) {
    FILE *fp = fopen(path, "wb");
    fwrite(data, 1, n, fp);
    fclose(fp);
}

static void write_text(const char *path, const char *text) { write_bytes(path, text, strlen(text)); }

static void check_name(frig_ctx *ctx, const frig_photoset *set, size_t photo, const char *want) {
    char buf[256];
    CHECK(frig_clouds_file_name(ctx, set, photo, buf, sizeof buf) == FRIG_OK);
    if (strcmp(buf, want) != 0) {
        fprintf(stderr, "photo %zu: cloud file '%s', expected '%s'\n", photo, buf, want);
        test_failures++;
    }
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    const char *dir = test_temp_dir("clouds");
    char ws[4096], path[4200];
    snprintf(ws, sizeof ws, "%s/ws", dir);

    frig_photoset *set = NULL;
    CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
    const char *photos[] = {"/a/photo_001.jpg", "/b/photo_001.png", "/c/photo_001_2.jpg", "/d/noext", "/e/x.y.jpg"};
    for (size_t i = 0; i < 5; i++) CHECK(frig_photoset_add(ctx, set, photos[i], NULL) == FRIG_OK);
    check_name(ctx, set, 0, "photo_001.ply");
    check_name(ctx, set, 1, "photo_001_2.ply");
    check_name(ctx, set, 2, "photo_001_2_2.ply"); /* its own stem was taken by photo 1 */
    check_name(ctx, set, 3, "noext.ply");
    check_name(ctx, set, 4, "x.y.ply");
    char small[4];
    CHECK(frig_clouds_file_name(ctx, set, 0, small, sizeof small) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_clouds_file_name(ctx, set, 9, path, sizeof path) == FRIG_ERR_INVALID_ARGUMENT);

    /* Handle: set, read back, replace, clear. */
    frig_clouds *c = NULL;
    CHECK(frig_clouds_create(ctx, 5, &c) == FRIG_OK && frig_clouds_photo_count(c) == 5);
    enum { N = 1000 };
    float *xyz = malloc(sizeof(float) * 3 * N), *nrm = malloc(sizeof(float) * 3 * N), *conf = malloc(sizeof(float) * N);
    for (int i = 0; i < N; i++) {
        for (int d = 0; d < 3; d++) xyz[3 * i + d] = (float)(0.001 * i - 0.3 * d + 1.0 / 3.0);
        nrm[3 * i] = 0.6f, nrm[3 * i + 1] = 0.0f, nrm[3 * i + 2] = 0.8f;
        conf[i] = (float)i / N;
    }
    CHECK(frig_clouds_set(ctx, c, 0, N, xyz, nrm, conf) == FRIG_OK);
    CHECK(frig_clouds_set(ctx, c, 2, 3, xyz + 30, nrm, conf) == FRIG_OK);
    CHECK(frig_clouds_set(ctx, c, 5, 3, xyz, nrm, conf) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_clouds_set(ctx, c, 1, 3, xyz, NULL, conf) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_clouds_count(c, 0) == N && frig_clouds_count(c, 1) == 0 && frig_clouds_count(c, 2) == 3);
    CHECK(frig_clouds_xyz(c, 1) == NULL && frig_clouds_count(c, 77) == 0);
    CHECK(frig_clouds_xyz(c, 2)[0] == xyz[30]);

    /* Round trip: every float back bit for bit. A stale file and one of a photo that has no
     * cloud are removed; files that are not .ply stay. */
    snprintf(path, sizeof path, "%s/clouds", ws);
    char cmd[4400];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", path);
    CHECK(system(cmd) == 0);
    snprintf(path, sizeof path, "%s/clouds/old_photo.ply", ws);
    write_text(path, "stale");
    snprintf(path, sizeof path, "%s/clouds/noext.ply", ws);
    write_text(path, "photo 3 has no cloud now");
    snprintf(path, sizeof path, "%s/clouds/notes.txt", ws);
    write_text(path, "kept");
    CHECK(frig_clouds_save(ctx, c, set, ws) == FRIG_OK);
    snprintf(path, sizeof path, "%s/clouds/old_photo.ply", ws);
    CHECK(access(path, F_OK) != 0);
    snprintf(path, sizeof path, "%s/clouds/noext.ply", ws);
    CHECK(access(path, F_OK) != 0);
    snprintf(path, sizeof path, "%s/clouds/notes.txt", ws);
    CHECK(access(path, F_OK) == 0);
    snprintf(path, sizeof path, "%s/clouds/photo_001_2_2.ply", ws);
    CHECK(access(path, F_OK) == 0);

    frig_clouds *back = NULL;
    CHECK(frig_clouds_load(ctx, set, ws, &back) == FRIG_OK);
    CHECK(back && frig_clouds_count(back, 0) == N && frig_clouds_count(back, 2) == 3 && frig_clouds_count(back, 1) == 0);
    if (back && frig_clouds_count(back, 0) == N) {
        CHECK(memcmp(frig_clouds_xyz(back, 0), xyz, sizeof(float) * 3 * N) == 0);
        CHECK(memcmp(frig_clouds_normals(back, 0), nrm, sizeof(float) * 3 * N) == 0);
        CHECK(memcmp(frig_clouds_confidence(back, 0), conf, sizeof(float) * N) == 0);
    }
    frig_clouds_free(back);
    back = NULL;

    /* A margin: after the cloud's points in the arrays, in clouds/margin/ on disk, the cloud's own
     * file unchanged; gone from disk when the cloud loses it, and with frig_clouds_set. */
    snprintf(path, sizeof path, "%s/clouds/photo_001.ply", ws);
    size_t plain_size = 0;
    unsigned char *plain = test_read_file(path, &plain_size);
    CHECK(frig_clouds_set_margin(ctx, c, 1, 3, xyz, nrm, conf) == FRIG_ERR_INVALID_ARGUMENT); /* no cloud */
    CHECK(frig_clouds_set_margin(ctx, c, 0, 5, xyz + 60, nrm, NULL) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_clouds_set_margin(ctx, c, 0, 5, xyz + 60, nrm + 60, conf + 20) == FRIG_OK);
    CHECK(frig_clouds_count(c, 0) == N && frig_clouds_margin_count(c, 0) == 5 && frig_clouds_margin_count(c, 2) == 0);
    CHECK(frig_clouds_xyz(c, 0)[3 * N] == xyz[60] && frig_clouds_confidence(c, 0)[N + 4] == conf[24]);
    CHECK(frig_clouds_xyz(c, 0)[0] == xyz[0]);
    CHECK(frig_clouds_save(ctx, c, set, ws) == FRIG_OK);
    size_t again_size = 0;
    unsigned char *again = test_read_file(path, &again_size);
    CHECK(plain && again && again_size == plain_size && memcmp(plain, again, plain_size) == 0);
    free(plain), free(again);
    snprintf(path, sizeof path, "%s/clouds/margin/photo_001.ply", ws);
    CHECK(access(path, F_OK) == 0);
    snprintf(path, sizeof path, "%s/clouds/margin/photo_001_2_2.ply", ws);
    CHECK(access(path, F_OK) != 0); /* photo 2 has no margin */
    CHECK(frig_clouds_load(ctx, set, ws, &back) == FRIG_OK);
    CHECK(back && frig_clouds_count(back, 0) == N && frig_clouds_margin_count(back, 0) == 5 &&
          frig_clouds_margin_count(back, 2) == 0);
    if (back && frig_clouds_margin_count(back, 0) == 5) {
        CHECK(memcmp(frig_clouds_xyz(back, 0), xyz, sizeof(float) * 3 * N) == 0);
        CHECK(memcmp(frig_clouds_xyz(back, 0) + 3 * N, xyz + 60, sizeof(float) * 15) == 0);
        CHECK(memcmp(frig_clouds_normals(back, 0) + 3 * N, nrm + 60, sizeof(float) * 15) == 0);
        CHECK(memcmp(frig_clouds_confidence(back, 0) + N, conf + 20, sizeof(float) * 5) == 0);
    }
    frig_clouds_free(back);
    back = NULL;
    CHECK(frig_clouds_set_margin(ctx, c, 0, 0, NULL, NULL, NULL) == FRIG_OK && frig_clouds_margin_count(c, 0) == 0);
    CHECK(frig_clouds_save(ctx, c, set, ws) == FRIG_OK);
    snprintf(path, sizeof path, "%s/clouds/margin/photo_001.ply", ws);
    CHECK(access(path, F_OK) != 0); /* a margin lost on a rerun leaves no old file */
    CHECK(frig_clouds_set_margin(ctx, c, 2, 2, xyz, nrm, conf) == FRIG_OK && frig_clouds_margin_count(c, 2) == 2);
    /* the margin copied from the cloud's own (borrowed) arrays: read before they are replaced */
    CHECK(frig_clouds_set_margin(ctx, c, 2, 3, frig_clouds_xyz(c, 2), frig_clouds_normals(c, 2),
                                 frig_clouds_confidence(c, 2)) == FRIG_OK);
    CHECK(frig_clouds_margin_count(c, 2) == 3 && memcmp(frig_clouds_xyz(c, 2) + 9, xyz + 30, sizeof(float) * 9) == 0);
    CHECK(memcmp(frig_clouds_xyz(c, 2), xyz + 30, sizeof(float) * 9) == 0);
    CHECK(frig_clouds_set(ctx, c, 2, 3, xyz + 30, nrm, conf) == FRIG_OK && frig_clouds_margin_count(c, 2) == 0);
    CHECK(frig_clouds_set(ctx, c, 0, 0, NULL, NULL, NULL) == FRIG_OK && frig_clouds_count(c, 0) == 0);

    /* Other PLY layouts: doubles, extra properties, no normals or confidence. */
    frig_clouds *one = NULL;
    CHECK(frig_clouds_create(ctx, 1, &one) == FRIG_OK);
    {
        const char head[] = "ply\nformat binary_little_endian 1.0\ncomment made by hand\nelement vertex 2\n"
                            "property uchar red\nproperty double x\nproperty double y\nproperty double z\n"
                            "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
        unsigned char buf[512];
        size_t n = strlen(head);
        memcpy(buf, head, n);
        double v[6] = {1.5, -2.25, 3.0, 4.0, 5.0, -6.125};
        for (int i = 0; i < 2; i++) {
            buf[n++] = 200;
            memcpy(buf + n, v + 3 * i, 24);
            n += 24;
        }
        snprintf(path, sizeof path, "%s/doubles.ply", dir);
        write_bytes(path, buf, n);
        CHECK(frig_clouds_load_ply(ctx, one, 0, path) == FRIG_OK);
        CHECK(frig_clouds_count(one, 0) == 2);
        if (frig_clouds_count(one, 0) == 2) {
            CHECK(frig_clouds_xyz(one, 0)[5] == -6.125f && frig_clouds_xyz(one, 0)[1] == -2.25f);
            CHECK(frig_clouds_normals(one, 0)[0] == 0.0f && frig_clouds_confidence(one, 0)[1] == 1.0f);
        }
    }

    /* Damaged files: each is a status with a sentence, and the slot keeps what it had. */
    snprintf(path, sizeof path, "%s/clouds/photo_001.ply", ws);
    CHECK(frig_clouds_save(ctx, c, set, ws) == FRIG_OK); /* photo 0 has no cloud: its file is gone */
    CHECK(access(path, F_OK) != 0);
    CHECK(frig_clouds_set(ctx, c, 0, N, xyz, nrm, conf) == FRIG_OK);
    CHECK(frig_clouds_save(ctx, c, set, ws) == FRIG_OK);
    size_t size = 0;
    unsigned char *good = test_read_file(path, &size);
    CHECK(good && size > 3 * N * 4);
    struct {
        const char *what;
        const char *text; /* replaces the file's text; NULL: truncate */
        size_t cut;
        frig_status want;
    } bad[] = {
        {"empty", "", 0, FRIG_ERR_CORRUPT},
        {"not ply", "hello\nworld\n", 0, FRIG_ERR_CORRUPT},
        {"no end", "ply\nformat binary_little_endian 1.0\nelement vertex 1\n", 0, FRIG_ERR_TRUNCATED},
        {"ascii", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", 0,
         FRIG_ERR_UNSUPPORTED},
        {"no z", "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                 "end_header\n", 0, FRIG_ERR_CORRUPT},
        {"half normals", "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
                         "property float y\nproperty float z\nproperty float nx\nend_header\n", 0, FRIG_ERR_CORRUPT},
        {"bad count", "ply\nformat binary_little_endian 1.0\nelement vertex -3\nproperty float x\nend_header\n", 0,
         FRIG_ERR_CORRUPT},
        {"huge count", "ply\nformat binary_little_endian 1.0\nelement vertex 99999999999\nproperty float x\n"
                       "property float y\nproperty float z\nend_header\n", 0, FRIG_ERR_TRUNCATED},
        {"bad type", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty quad x\nend_header\n", 0,
         FRIG_ERR_CORRUPT},
        {"face first", "ply\nformat binary_little_endian 1.0\nelement face 1\nend_header\n", 0, FRIG_ERR_UNSUPPORTED},
        {"truncated data", NULL, size - 100, FRIG_ERR_TRUNCATED},
        {"truncated header", NULL, 40, FRIG_ERR_TRUNCATED},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0] && good; k++) {
        if (bad[k].text) write_text(path, bad[k].text);
        else write_bytes(path, good, bad[k].cut);
        frig_status s = frig_clouds_load_ply(ctx, c, 0, path);
        if (s != bad[k].want || !*frig_ctx_errmsg(ctx)) {
            fprintf(stderr, "%s: status %d (%s), expected %d\n", bad[k].what, s, frig_ctx_errmsg(ctx), bad[k].want);
            test_failures++;
        }
        CHECK(frig_clouds_count(c, 0) == N);
        CHECK(frig_clouds_load(ctx, set, ws, &back) == bad[k].want && back == NULL);
    }
    /* Every single-byte cut of the header and a NaN point. */
    for (size_t cut = 0; cut < 200 && good; cut++) {
        write_bytes(path, good, cut);
        CHECK(frig_clouds_load_ply(ctx, c, 0, path) != FRIG_OK);
    }
    if (good) {
        unsigned char *nan_file = malloc(size);
        memcpy(nan_file, good, size);
        const char *end = strstr((const char *)nan_file, "end_header\n");
        size_t at = (size_t)(end - (const char *)nan_file) + 11;
        float q = NAN;
        memcpy(nan_file + at + 4, &q, 4);
        write_bytes(path, nan_file, size);
        CHECK(frig_clouds_load_ply(ctx, c, 0, path) == FRIG_ERR_CORRUPT);
        free(nan_file);
    }
    snprintf(path, sizeof path, "%s/nothing.ply", dir);
    CHECK(frig_clouds_load_ply(ctx, c, 0, path) == FRIG_ERR_NOT_FOUND);

    free(good);
    free(xyz), free(nrm), free(conf);
    frig_clouds_free(one);
    frig_clouds_free(c);
    frig_photoset_free(set);
    frig_ctx_free(ctx);
    return test_result("test_clouds");
}
