/* Pictures of the detect stage for a person to check (paper section 4.2, the detected landmarks
 * of Figure 4.x): each photo with every face's box (the subject thick and green, others
 * yellow, user-supplied ones blue), its 68 landmarks, and the status written on it; an
 * unreadable photo becomes a gray card carrying its status and reason. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/detector.h"
#include "image/image.h"
#include "io/file.h"
#include "raster/draw.h"
#include "workspace/photoset.h"

static const uint8_t GREEN[3] = {40, 230, 60}, YELLOW[3] = {255, 210, 0}, BLUE[3] = {60, 140, 255};
static const uint8_t RED[3] = {255, 60, 50}, WHITE[3] = {255, 255, 255}, BLACK[3] = {0, 0, 0};

/* A label on a dark band, wrapped to the image's width only by its newlines. */
static void label(frig_image *img, int x, int y, const char *text, int scale, const uint8_t rgb[3]) {
    int tw, th;
    fr_text_size(text, scale, &tw, &th);
    fr_fill_rect(img, x - scale, y - scale, x + tw + scale, y + th + scale, BLACK, 0.6);
    fr_draw_text(img, x, y, text, scale, rgb);
}

static void draw_face(frig_image *img, const fr_face *f, int subject, double unit) {
    const uint8_t *c = f->source == FRIG_FACE_USER ? BLUE : subject ? GREEN : YELLOW;
    int t = (int)fmax(1.0, round(unit * (subject ? 3.0 : 1.5)));
    fr_draw_rect(img, (int)floor(f->box[0]), (int)floor(f->box[1]), (int)ceil(f->box[0] + f->box[2]),
                 (int)ceil(f->box[1] + f->box[3]), t, c);
    if (!f->has_landmarks) return;
    for (int k = 0; k < FRIG_LANDMARK_COUNT; k++)
        fr_draw_disc(img, f->landmarks[2 * k], f->landmarks[2 * k + 1], fmax(1.0, 1.6 * unit), subject ? RED : c, 1);
}

/* The status line: "ok: 2 faces (subject 0, frontal)" or "no_face: no face found". */
static void status_text(const fr_photo *p, char *buf, size_t size) {
    static const char *const src[] = {"frontal", "profile", "profile mirrored", "user", "ssd"};
    const char *name = frig_photo_status_name(p->status);
    if (p->status == FRIG_PHOTO_OK && p->subject >= 0 && (size_t)p->subject < p->face_count) {
        const fr_face *f = &p->faces[p->subject];
        char dist[48] = "";
        if (!isnan(f->identity_distance)) snprintf(dist, sizeof dist, ", identity distance %.2f", f->identity_distance);
        snprintf(buf, size, "%s: %zu face%s (subject %ld, %s%s)", name ? name : "?", p->face_count,
                 p->face_count == 1 ? "" : "s", p->subject, src[(unsigned)f->source <= FRIG_FACE_SSD ? f->source : 0],
                 dist);
    }
    else
        snprintf(buf, size, "%s%s%.200s", name ? name : "?", p->reason && *p->reason ? ": " : "",
                 p->reason ? p->reason : "");
}

/* Break a long line at spaces so it fits 'cols' characters per line (in place). */
static void wrap(char *s, int cols) {
    int col = 0;
    char *last_space = NULL;
    for (char *c = s; *c; c++, col++) {
        if (*c == ' ') last_space = c;
        if (col >= cols && last_space) {
            *last_space = '\n';
            col = (int)(c - last_space);
            last_space = NULL;
        }
    }
}

static frig_status overlay_photo(frig_ctx *child, const fr_photo *p, const char *path) {
    frig_image *img = NULL;
    if (p->status == FRIG_PHOTO_UNREADABLE || frig_image_load(child, p->path, 0, &img) != FRIG_OK) {
        frig_ctx_clear_error(child);
        frig_status st = frig_image_create(child, 480, 360, 3, &img);
        if (st) return st;
        memset(img->pixels, 90, img->stride * (size_t)img->height);
    }
    double unit = fmax(1.0, fmax(img->width, img->height) / 500.0);
    for (size_t k = 0; k < p->face_count; k++)
        if ((long)k != p->subject) draw_face(img, &p->faces[k], 0, unit);
    if (p->subject >= 0 && (size_t)p->subject < p->face_count) draw_face(img, &p->faces[p->subject], 1, unit);
    char text[512];
    status_text(p, text, sizeof text);
    int scale = (int)fmax(1.0, round(unit));
    wrap(text, (int)fmax(10.0, (img->width - 8.0) / (6.0 * scale)));
    label(img, 4 * scale, 4 * scale, text, scale, p->status == FRIG_PHOTO_OK ? WHITE : RED);
    frig_status st = frig_image_save_jpeg(child, img, path);
    frig_image_free(img);
    return st;
}

/* NNN_STEM.jpg: the photo's index (so names never collide) and its name without extension. */
static char *overlay_name(const char *dir, size_t index, size_t count, const char *photo) {
    const char *base = fr_path_base(photo), *dot = strrchr(base, '.');
    int stem = (int)(dot && dot != base ? (size_t)(dot - base) : strlen(base));
    int digits = 1;
    for (size_t c = count; c >= 10; c /= 10) digits++;
    size_t size = strlen(base) + 40;
    char *name = malloc(size);
    if (!name) return NULL;
    snprintf(name, size, "%0*zu_%.*s.jpg", digits, index, stem, base);
    char *path = fr_path_join(dir, name);
    free(name);
    return path;
}

typedef struct overlay_job {
    const frig_photoset *set;
    const char *dir;
} overlay_job;

static frig_status overlay_item(frig_ctx *child, size_t i, void *user) {
    const overlay_job *job = user;
    char *path = overlay_name(job->dir, i, job->set->count, job->set->photos[i].path);
    frig_status st = path ? overlay_photo(child, &job->set->photos[i], path) : fr_nomem(child, "a path");
    free(path);
    return st;
}

frig_status frig_detect_write_overlays(frig_ctx *ctx, const frig_photoset *set, const char *dir) {
    if (!set || !dir) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detect_write_overlays: NULL argument");
    frig_status st = fr_make_dirs(ctx, dir);
    if (st) return st;
    overlay_job job = {set, dir};
    return fr_parallel_items(ctx, set->count, "overlays", overlay_item, &job);
}
