/* The photo set and its report.json: exact round trip (numbers included), statuses,
 * subject choice, validation of damaged reports. */
#include <stdlib.h>
#include <string.h>

#include "frig/frig.h"
#include "frig/photoset.h"
#include "io/json_writer.h"
#include "testing.h"

static void write_text(const char *path, const char *text) {
    FILE *fp = fopen(path, "w");
    fputs(text, fp);
    fclose(fp);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    const char *dir = test_temp_dir("photoset");
    char ws[4096];
    snprintf(ws, sizeof ws, "%s/ws", dir);

    /* Numbers written by the JSON writer read back bit-exactly. */
    const double probes[] = {0.1, 1.0 / 3.0, 123.456, -7.25e-9, 1e300, 2.5, 136.00000000000003};
    for (size_t k = 0; k < sizeof probes / sizeof probes[0]; k++) {
        char buf[32];
        fr_json_format_number(buf, probes[k]);
        CHECK(strtod(buf, NULL) == probes[k]);
    }
    char buf[32];
    fr_json_format_number(buf, 123.456);
    CHECK(strcmp(buf, "123.456") == 0);

    frig_photoset *set = NULL;
    CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
    size_t a, b, c, f;
    frig_photoset_add(ctx, set, "/photos/a \"quoted\".jpg", &a);
    frig_photoset_add(ctx, set, "/photos/b.png", &b);
    frig_photoset_add(ctx, set, "/photos/c.jpg", &c);
    CHECK(a == 0 && b == 1 && c == 2 && frig_photoset_count(set) == 3);
    double box[4] = {10.5, 20.25, 100, 120}, lm[136];
    for (int k = 0; k < 136; k++) lm[k] = k * 1.1 + 1.0 / 3.0;
    CHECK(frig_photoset_add_face(ctx, set, a, box, 0.75, FRIG_FACE_FRONTAL, lm, &f) == FRIG_OK && f == 0);
    box[0] = 300;
    CHECK(frig_photoset_add_face(ctx, set, a, box, 0.5, FRIG_FACE_PROFILE_MIRRORED, NULL, &f) == FRIG_OK && f == 1);
    CHECK(frig_photoset_set_subject(ctx, set, a, 0) == FRIG_OK);
    CHECK(frig_photoset_set_subject(ctx, set, a, 2) == FRIG_ERR_INVALID_ARGUMENT);
    frig_photoset_set_status(ctx, set, a, FRIG_PHOTO_OK, NULL);
    frig_photoset_set_size(ctx, set, a, 640, 480);
    frig_photoset_set_filter(ctx, set, a, 1.5, 0.9, 6.0, 0);
    frig_photoset_set_status(ctx, set, b, FRIG_PHOTO_UNREADABLE, "b.png: PNG data ends too early");
    frig_photoset_set_status(ctx, set, c, FRIG_PHOTO_NO_FACE, "no face found at any scale");
    double nan_box[4] = {NAN, 0, 1, 1};
    CHECK(frig_photoset_add_face(ctx, set, c, nan_box, 0, FRIG_FACE_FRONTAL, NULL, NULL) ==
          FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_photoset_save(ctx, set, ws) == FRIG_OK);

    frig_photoset *back = NULL;
    CHECK(frig_photoset_load(ctx, ws, &back) == FRIG_OK);
    CHECK(back && frig_photoset_count(back) == 3);
    if (back) {
        CHECK(strcmp(frig_photoset_path(back, 0), "/photos/a \"quoted\".jpg") == 0);
        CHECK(frig_photoset_status(back, 1) == FRIG_PHOTO_UNREADABLE);
        CHECK(strcmp(frig_photoset_reason(back, 1), "b.png: PNG data ends too early") == 0);
        CHECK(frig_photoset_face_count(back, 0) == 2 && frig_photoset_subject(back, 0) == 0);
        double lm2[136], box2[4];
        CHECK(frig_photoset_face_landmarks(back, 0, 0, lm2) == FRIG_OK && memcmp(lm, lm2, sizeof lm) == 0);
        CHECK(frig_photoset_face_landmarks(back, 0, 1, lm2) == FRIG_ERR_STATE);
        CHECK(frig_photoset_face_box(back, 0, 1, box2) == FRIG_OK && box2[0] == 300 && box2[1] == 20.25);
        CHECK(frig_photoset_face_source(back, 0, 1) == FRIG_FACE_PROFILE_MIRRORED);
        double e;
        int round;
        CHECK(frig_photoset_filter(back, 0, &e, NULL, NULL, &round) && e == 1.5 && round == 0);
        CHECK(!frig_photoset_filter(back, 1, NULL, NULL, NULL, NULL));
        int w, h;
        frig_photoset_size(back, 0, &w, &h);
        CHECK(w == 640 && h == 480);
    }
    /* Saving what was loaded gives the same bytes. */
    char ws2[4096];
    snprintf(ws2, sizeof ws2, "%s/ws2", dir);
    CHECK(back && frig_photoset_save(ctx, back, ws2) == FRIG_OK);
    char cmd[9000];
    snprintf(cmd, sizeof cmd, "cmp -s '%s/report.json' '%s/report.json'", ws, ws2);
    CHECK(system(cmd) == 0);
    frig_photoset_free(back);

    /* Damaged reports: a status and a sentence, never a crash. */
    char rp[4200];
    snprintf(rp, sizeof rp, "%s/report.json", ws2);
    const char *damaged[] = {
        "", "{", "[]", "{\"format\": \"other\"}", "{\"format\": \"frig-report\", \"version\": 1}",
        "{\"format\": \"frig-report\", \"version\": 99, \"photos\": []}",
        "{\"format\": \"frig-report\", \"version\": 1, \"photos\": [{\"status\": \"ok\"}]}",
        "{\"format\": \"frig-report\", \"version\": 1, \"photos\": [{\"file\": \"x\", \"status\": \"great\"}]}",
        "{\"format\": \"frig-report\", \"version\": 1, \"photos\": [{\"file\": \"x\", \"status\": \"ok\", "
        "\"faces\": [{\"box\": [1, 2, 3], \"source\": \"frontal\"}]}]}",
        "{\"format\": \"frig-report\", \"version\": 1, \"photos\": [{\"file\": \"x\", \"status\": \"ok\", "
        "\"faces\": [{\"box\": [1, 2, 3, 4], \"source\": \"frontal\", \"landmarks\": [[1, 2]]}]}]}",
        "{\"format\": \"frig-report\", \"version\": 1, \"photos\": [{\"file\": \"x\", \"status\": \"ok\", "
        "\"faces\": [], \"subject\": 3}]}",
    };
    for (size_t k = 0; k < sizeof damaged / sizeof damaged[0]; k++) {
        write_text(rp, damaged[k]);
        frig_photoset *d = NULL;
        frig_status s = frig_photoset_load(ctx, ws2, &d);
        printf("damaged report %zu -> %s: %s\n", k, frig_strerror(s), frig_ctx_errmsg(ctx));
        CHECK((s == FRIG_ERR_CORRUPT || s == FRIG_ERR_UNSUPPORTED) && d == NULL);
        CHECK(strstr(frig_ctx_errmsg(ctx), "report.json") != NULL);
    }
    char missing[4200];
    snprintf(missing, sizeof missing, "%s/none", dir);
    frig_photoset *d = NULL;
    CHECK(frig_photoset_load(ctx, missing, &d) == FRIG_ERR_NOT_FOUND);
    CHECK(strstr(frig_ctx_errmsg(ctx), "frig detect") != NULL);
    frig_photoset_free(set);
    frig_ctx_free(ctx);
    return test_result("test_photoset");
}
