/* Pictures of a rig (frig_rig_render, frig_rig_save_contact_sheet): sizes, the framing (the
 * background in the corners, the face in the middle), what an expression changes (jawOpen
 * moves the lower face, not the scalp), the painted eyes (a dark pupil where the iris is),
 * the same bytes whatever the thread count, and the refusals. */
#include <stdlib.h>
#include <string.h>

#include "model_fixture.h"
#include "testing.h"

static const uint8_t *px(const frig_image *img, int x, int y) {
    return frig_image_pixels(img) + (size_t)y * frig_image_stride(img) + 3 * (size_t)x;
}

/* Rows in y0..y1-1 where some sample differs by more than 'tol' levels. */
static int rows_differ(const frig_image *a, const frig_image *b, int y0, int y1, int tol) {
    int n = 0;
    for (int y = y0; y < y1; y++) {
        int differs = 0;
        for (int x = 0; x < 3 * frig_image_width(a); x++) differs |= abs(px(a, 0, y)[x] - px(b, 0, y)[x]) > tol;
        n += differs;
    }
    return n;
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    frig_model *m = fixture_model(ctx);
    if (!m) {
        frig_ctx_free(ctx);
        return test_skip("no ICT-FaceKit model (../shared/ict-facekit)");
    }
    frig_rig *r = NULL;
    CHECK(frig_rig_from_model(ctx, m, NULL, &r) == FRIG_OK);
    frig_model_free(m);
    int n = frig_rig_shape_count(r), S = 120;
    double *w = calloc((size_t)n, sizeof *w);
    frig_image *neutral = NULL, *again = NULL, *jaw = NULL, *big = NULL;
    CHECK(frig_rig_render(ctx, r, NULL, 0, 0, FRIG_FRAME_FACE, S, S, &neutral) == FRIG_OK);
    CHECK(frig_rig_render(ctx, r, w, 0, 0, FRIG_FRAME_FACE, S, S, &again) == FRIG_OK); /* all-zero weights */
    w[frig_rig_shape_find(r, "jawOpen")] = 1.0;
    CHECK(frig_rig_render(ctx, r, w, 0, 0, FRIG_FRAME_FACE, S, S, &jaw) == FRIG_OK);
    if (neutral && again && jaw) {
        CHECK(frig_image_width(neutral) == S && frig_image_height(neutral) == S && frig_image_channels(neutral) == 3);
        CHECK(rows_differ(neutral, again, 0, S, 0) == 0);
        const uint8_t *corner = px(neutral, 0, 0), *centre = px(neutral, S / 2, S / 2);
        printf("neutral: corner %d %d %d, centre %d %d %d\n", corner[0], corner[1], corner[2], centre[0], centre[1],
               centre[2]);
        CHECK(corner[0] < 100 && corner[2] < 100 && abs(corner[0] - corner[2]) < 12); /* dark grey background */
        CHECK(centre[0] > 120 && centre[0] > centre[2] + 15);                       /* warm skin */
        /* ICT's jawOpen moves the scalp by a hair: at most 3 levels there */
        int top = rows_differ(neutral, jaw, 0, S / 8, 3), bottom = rows_differ(neutral, jaw, S / 2, S, 3);
        printf("jawOpen changes %d of the top %d rows and %d of the lower %d (by more than 3 levels)\n", top, S / 8,
               bottom, S / 2);
        CHECK(top == 0 && bottom > S / 4);
    }
    /* The eyes, 3/4 up the head in a head-framed picture: the darkest pixels of the picture's
     * eye band are the pupils (well under the skin and the sclera). */
    CHECK(frig_rig_render(ctx, r, NULL, 0, 0, FRIG_FRAME_FACE, 400, 400, &big) == FRIG_OK);
    if (big) {
        int darkest = 255, dx = -1, dy = -1;
        for (int y = 120; y < 190; y++)
            for (int x = 100; x < 300; x++) {
                const uint8_t *p = px(big, x, y);
                int v = (p[0] + p[1] + p[2]) / 3;
                if (v < darkest) darkest = v, dx = x, dy = y;
            }
        printf("darkest pixel of the eye band: %d at (%d, %d)\n", darkest, dx, dy);
        CHECK(darkest < 60);
    }
    /* Contact sheets: 1 and 2 threads give the same bytes. */
    const char *tmp = test_temp_dir("rig_render");
    char a[4200], b[4200];
    snprintf(a, sizeof a, "%s/sheet1.png", tmp);
    snprintf(b, sizeof b, "%s/sheet2.png", tmp);
    frig_ctx_set_threads(ctx, 1);
    CHECK(frig_rig_save_contact_sheet(ctx, r, 48, 8, a) == FRIG_OK);
    frig_ctx_set_threads(ctx, 2);
    CHECK(frig_rig_save_contact_sheet(ctx, r, 48, 8, b) == FRIG_OK);
    size_t na, nb;
    unsigned char *da = test_read_file(a, &na), *db = test_read_file(b, &nb);
    CHECK(da && db && na == nb && memcmp(da, db, na) == 0);
    free(da), free(db);
    frig_image *sheet = NULL;
    CHECK(frig_image_load(ctx, a, 0, &sheet) == FRIG_OK);
    if (sheet) {
        printf("contact sheet: %d x %d\n", frig_image_width(sheet), frig_image_height(sheet));
        CHECK(frig_image_width(sheet) == 8 * 48 + 9 * 4); /* 56 pictures: neutral + 55 targets, 7 rows */
        /* mouthClose's picture is the rig at jawOpen 1 and mouthClose 1 (alone it pushes the lower
         * lip through the upper one) */
        int cell = -1, label_h = (frig_image_height(sheet) - 8 * 4) / 7 - 48;
        for (int i = 0; i < frig_rig_target_count(r); i++)
            if (!strcmp(frig_rig_target_name(r, i), "mouthClose")) cell = i + 1;
        double *wc = calloc((size_t)frig_rig_shape_count(r), sizeof(double));
        frig_image *both = NULL, *alone = NULL;
        int kc = frig_rig_shape_find(r, "mouthClose"), kj = frig_rig_shape_find(r, "jawOpen");
        CHECK(cell > 0 && kc >= 0 && kj >= 0 && wc);
        if (cell > 0 && kc >= 0 && kj >= 0 && wc) {
            wc[kc] = 1.0;
            CHECK(frig_rig_render(ctx, r, wc, 0, 0, FRIG_FRAME_FACE, 48, 48, &alone) == FRIG_OK);
            wc[kj] = 1.0;
            CHECK(frig_rig_render(ctx, r, wc, 0, 0, FRIG_FRAME_FACE, 48, 48, &both) == FRIG_OK);
        }
        if (both && alone) {
            int x0 = 4 + (cell % 8) * (48 + 4), y0 = 4 + (cell / 8) * (48 + label_h + 4);
            double d_both = 0, d_alone = 0;
            for (int y = 0; y < 48; y++)
                for (int x = 0; x < 48; x++)
                    for (int c = 0; c < 3; c++) {
                        int v = px(sheet, x0 + x, y0 + y)[c];
                        d_both += abs(v - px(both, x, y)[c]), d_alone += abs(v - px(alone, x, y)[c]);
                    }
            d_both /= 48 * 48 * 3, d_alone /= 48 * 48 * 3;
            printf("mouthClose's cell against the rig at jawOpen + mouthClose: %.3f levels, at mouthClose alone %.3f\n",
                   d_both, d_alone);
            CHECK(d_both < 0.5 && d_alone > 2.0);
        }
        frig_image_free(both), frig_image_free(alone);
        free(wc);
    }
    /* Refusals. */
    frig_image *none = NULL;
    CHECK(frig_rig_render(ctx, r, NULL, 0, 0, FRIG_FRAME_FACE, 8, 8, &none) == FRIG_ERR_INVALID_ARGUMENT && !none);
    CHECK(frig_rig_render(ctx, r, NULL, NAN, 0, FRIG_FRAME_FACE, 64, 64, &none) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_rig_save_contact_sheet(ctx, r, 48, 0, a) == FRIG_ERR_INVALID_ARGUMENT);
    frig_image_free(neutral), frig_image_free(again), frig_image_free(jaw), frig_image_free(big), frig_image_free(sheet);
    free(w);
    frig_rig_free(r);
    frig_ctx_free(ctx);
    return test_result("test_rig_render");
}
