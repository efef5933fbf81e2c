/* OUT/report.html: the page a technical artist opens first after frig run. One file that
 * opens from disk with no network (images beside it in OUT/report/, plots inline as SVG):
 * what came in and what was used (photos dropped, by reason), the rig rendered by libfrig's
 * own rasterizer (neutral from three sides, every blendshape on a contact sheet), the error
 * curves (cumulative distributions of landmark, fit, shape-from-shading and filter errors, as
 * the paper's figures show them), the sfs stage's overlays and albedo, retarget's rigs before and
 * after, the time and memory of each stage, and every photo with its status, reason and overlays. */
#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <frig/fit.h>
#include <frig/retarget.h>
#include <frig/sfs.h>

#include "run.h"

#define THUMB 220
#define PAPER_SECONDS 3000.0 /* the dissertation's pipeline on 100 photos */

typedef struct page {
    char *data;
    size_t size, cap;
    int failed;
} page;

static void put(page *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(page *p, const char *fmt, ...) {
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        size_t room = p->cap - p->size;
        int n = p->cap ? vsnprintf(p->data + p->size, room, fmt, ap) : -2;
        va_end(ap);
        if (n >= 0 && (size_t)n < room) {
            p->size += (size_t)n;
            return;
        }
        size_t cap = p->cap ? 2 * p->cap : 1 << 16;
        while (n >= 0 && cap < p->size + (size_t)n + 1) cap *= 2;
        char *d = realloc(p->data, cap);
        if (!d) {
            p->failed = 1;
            return;
        }
        p->data = d, p->cap = cap;
    }
}

/* Text for HTML (element content and quoted attributes). */
static void put_text(page *p, const char *s) {
    for (; s && *s; s++) {
        switch (*s) {
        case '&': put(p, "&amp;"); break;
        case '<': put(p, "&lt;"); break;
        case '>': put(p, "&gt;"); break;
        case '"': put(p, "&quot;"); break;
        case '\'': put(p, "&#39;"); break;
        default: put(p, "%c", *s);
        }
    }
}

/* A path for href/src: percent-encoded where a URL needs it. */
static void put_url(page *p, const char *s) {
    for (; s && *s; s++) {
        unsigned char c = (unsigned char)*s;
        if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || strchr("-_./~", c)) put(p, "%c", c);
        else put(p, "%%%02X", c);
    }
}

/* path relative to the folder 'from' (both absolute). */
static void relative(const char *from, const char *path, char *out, size_t size) {
    /* the longest common run of whole components */
    size_t common = 0, i = 0;
    for (;; i++) {
        int fe = from[i] == 0 || from[i] == '/', pe = path[i] == 0 || path[i] == '/';
        if (fe && pe) {
            common = i;
            if (!from[i] || !path[i]) break;
        } else if (from[i] != path[i]) {
            break;
        }
    }
    size_t len = 0;
    out[0] = 0;
    for (const char *f = from + common; *f; f++)
        if (*f == '/' && f[1]) len += (size_t)snprintf(out + len, len < size ? size - len : 0, "../");
    const char *rest = path + common;
    while (*rest == '/') rest++;
    snprintf(out + len, len < size ? size - len : 0, "%s", rest);
}

static const char *status_class(frig_photo_status s) {
    switch (s) {
    case FRIG_PHOTO_OK: return "ok";
    case FRIG_PHOTO_OUTLIER: return "warn";
    case FRIG_PHOTO_DUPLICATE: return "dup";
    case FRIG_PHOTO_NO_FACE:
    case FRIG_PHOTO_FACE_TOO_SMALL: return "none";
    default: return "bad";
    }
}

static const char *status_words(frig_photo_status s) {
    switch (s) {
    case FRIG_PHOTO_OK: return "used";
    case FRIG_PHOTO_UNREADABLE: return "could not be read";
    case FRIG_PHOTO_NO_FACE: return "no face found";
    case FRIG_PHOTO_FACE_TOO_SMALL: return "face too small";
    case FRIG_PHOTO_OUTLIER: return "dropped by the filter: landmarks the rest of the set cannot explain";
    case FRIG_PHOTO_FIT_FAILED: return "the model fit failed";
    case FRIG_PHOTO_DUPLICATE: return "the same file as an earlier photo";
    case FRIG_PHOTO_OTHER_PERSON: return "another person than the set's subject";
    case FRIG_PHOTO_SFS_FAILED: return "fitted, but shape from shading could not read the face (the rig does not use its shading)";
    default: return "";
    }
}

/* ---- plots: cumulative distributions as inline SVG ---- */

typedef struct series {
    const char *name, *colour;
    double *v;
    size_t n;
} series;

static int by_value(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double nice_step(double range) {
    double s = pow(10, floor(log10(range / 5)));
    return range / s > 25 ? 5 * s : range / s > 10 ? 2 * s : s;
}

static void plot(page *p, const char *title, const char *xlabel, series *s, int ns, double xmax, const char *note) {
    const int W = 520, H = 300, L = 52, R = 16, T = 34, B = 44;
    double pw = W - L - R, ph = H - T - B;
    for (int k = 0; k < ns; k++) qsort(s[k].v, s[k].n, sizeof(double), by_value);
    if (!(xmax > 0)) {
        for (int k = 0; k < ns; k++)
            if (s[k].n) xmax = fmax(xmax, s[k].v[(size_t)(0.98 * (double)(s[k].n - 1))]);
        xmax = xmax > 0 ? xmax * 1.1 : 1;
    }
    put(p, "<figure class=\"plot\"><svg viewBox=\"0 0 %d %d\" width=\"%d\" height=\"%d\" role=\"img\" aria-label=\"", W, H, W, H);
    put_text(p, title);
    put(p, "\"><rect width=\"%d\" height=\"%d\" class=\"bg\"/>", W, H);
    put(p, "<text x=\"%d\" y=\"20\" class=\"title\">", L);
    put_text(p, title);
    put(p, "</text>");
    double step = nice_step(xmax);
    for (double x = 0; x <= xmax + 1e-9; x += step) {
        double px = L + pw * x / xmax;
        put(p, "<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%.1f\" class=\"grid\"/>", px, T, px, T + ph);
        put(p, "<text x=\"%.1f\" y=\"%.1f\" class=\"tick\" text-anchor=\"middle\">%g</text>", px, T + ph + 16, x);
    }
    for (int q = 0; q <= 4; q++) {
        double py = T + ph * (1 - q / 4.0);
        put(p, "<line x1=\"%d\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" class=\"grid\"/>", L, py, L + pw, py);
        put(p, "<text x=\"%d\" y=\"%.1f\" class=\"tick\" text-anchor=\"end\">%d%%</text>", L - 6, py + 4, 25 * q);
    }
    put(p, "<text x=\"%.1f\" y=\"%d\" class=\"axis\" text-anchor=\"middle\">", L + pw / 2, H - 6);
    put_text(p, xlabel);
    put(p, "</text>");
    for (int k = 0; k < ns; k++) {
        if (!s[k].n) continue;
        put(p, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"%d,%.1f", s[k].colour, L, T + ph);
        for (size_t i = 0; i < s[k].n; i++) {
            double x = L + pw * fmin(s[k].v[i], xmax) / xmax;
            put(p, " %.1f,%.1f %.1f,%.1f", x, T + ph * (1 - (double)i / s[k].n), x, T + ph * (1 - (double)(i + 1) / s[k].n));
        }
        put(p, " %.1f,%d\"/>", L + pw, T);
        double med = s[k].v[s[k].n / 2];
        double mx = L + pw * fmin(med, xmax) / xmax, my = T + ph * 0.5;
        put(p, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\"/>", mx, my, s[k].colour);
        /* legend, bottom right (where a cumulative curve never is) */
        double ly = T + ph - 10 - 16 * (ns - 1 - k);
        put(p, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"3\"/>", L + pw - 226,
            ly - 4, L + pw - 208, ly - 4, s[k].colour);
        put(p, "<text x=\"%.1f\" y=\"%.1f\" class=\"legend\">", L + pw - 202, ly);
        put_text(p, s[k].name);
        put(p, ": median %.3g (%zu)</text>", med, s[k].n);
    }
    put(p, "</svg>");
    if (note) {
        put(p, "<figcaption>");
        put_text(p, note);
        put(p, "</figcaption>");
    }
    put(p, "</figure>\n");
}

/* ---- pictures ---- */

static int make_pictures(run_ctx *r, int *have_rig) {
    cli_env *env = r->env;
    char path[4200], rig_path[4200], tex[4200];
    *have_rig = 0;
    frig_rig *rig = NULL;
    (void)rig_path;
    if (!r->rig_from[0] || frig_rig_load(env->ctx, r->rig_from, &rig)) return CLI_OK;
    struct stat st;
    if (stat(run_path(r, "textures/albedo.png", tex, sizeof tex), &st) == 0 && frig_rig_set_face_texture(env->ctx, rig, tex)) {
        frig_rig_free(rig);
        return cli_fail(env, "run");
    }
    static const struct {
        const char *file;
        double yaw;
    } views[] = {{"report/neutral_front.png", 0}, {"report/neutral_34.png", 35}, {"report/neutral_side.png", 80}};
    int rc = CLI_OK;
    for (size_t i = 0; i < sizeof views / sizeof views[0] && rc == CLI_OK; i++) {
        frig_image *img = NULL;
        if (frig_rig_render(env->ctx, rig, NULL, views[i].yaw, 0, FRIG_FRAME_HEAD, 360, 400, &img) ||
            frig_image_save_png(env->ctx, img, run_path(r, views[i].file, path, sizeof path)))
            rc = cli_fail(env, "run");
        frig_image_free(img);
    }
    if (rc == CLI_OK && frig_rig_save_contact_sheet(env->ctx, rig, 168, 8, run_path(r, "report/expressions.png", path, sizeof path)))
        rc = cli_fail(env, "run");
    frig_rig_free(rig);
    *have_rig = rc == CLI_OK;
    return rc;
}

/* Overlays by photo: detect's NNN_STEM.jpg (by index), fit's STEM.jpg. */
static void overlay_for(run_ctx *r, const frig_photoset *set, size_t i, char *rel, size_t size) {
    rel[0] = 0;
    const char *photo = frig_photoset_path(set, i), *base = strrchr(photo, '/') ? strrchr(photo, '/') + 1 : photo;
    const char *dot = strrchr(base, '.');
    int stem = (int)(dot && dot != base ? (size_t)(dot - base) : strlen(base));
    char path[4200];
    struct stat st;
    if (frig_photoset_fitted(set, i)) {
        snprintf(rel, size, "overlays/fit/%.*s.jpg", stem, base);
        if (stat(run_path(r, rel, path, sizeof path), &st) == 0) return;
    }
    char **files;
    size_t n;
    rel[0] = 0;
    if (run_list_files(run_path(r, "overlays/detect", path, sizeof path), &files, &n)) return;
    for (size_t k = 0; k < n; k++) {
        const char *name = strrchr(files[k], '/') + 1;
        char *end;
        unsigned long idx = strtoul(name, &end, 10);
        if (!rel[0] && end != name && *end == '_' && idx == i) snprintf(rel, size, "overlays/detect/%s", name);
        free(files[k]);
    }
    free(files);
}

/* ---- sections ---- */

/* The photos the rig was made from: usable and fitted. */
static size_t used_photos(const frig_photoset *set) {
    size_t used = 0;
    for (size_t i = 0; set && i < frig_photoset_count(set); i++)
        used += frig_photoset_status(set, i) == FRIG_PHOTO_OK && frig_photoset_fitted(set, i);
    return used;
}

/* An exported rig from fewer photos than RUN_FEW_PHOTOS: the report says the shape is held back. */
static int few_photos(const run_ctx *r, int have_rig, size_t used) {
    return have_rig && !r->stop[0] && used < RUN_FEW_PHOTOS;
}

static void section_summary(page *p, run_ctx *r, const frig_photoset *set, int have_rig) {
    size_t n = set ? frig_photoset_count(set) : 0, used = used_photos(set), counts[32] = {0};
    for (size_t i = 0; i < n; i++) {
        unsigned s = (unsigned)frig_photoset_status(set, i);
        if (s < 32) counts[s]++;
    }
    if (r->stop[0]) {
        put(p, "<div class=\"stop\"><b>The run stopped:</b> ");
        put_text(p, r->stop);
        put(p, ".</div>\n");
    }
    put(p, "<section class=\"cards\">");
    put(p, "<div class=\"card\"><div class=\"big\">%zu</div>photos in</div>", n);
    put(p, "<div class=\"card\"><div class=\"big ok\">%zu</div>used for the rig</div>", used);
    for (unsigned s = 0; s < 32; s++) {
        const char *name = frig_photo_status_name((frig_photo_status)s);
        if (!counts[s] || s == FRIG_PHOTO_OK || !name) continue;
        put(p, "<a class=\"card\" href=\"#%s\"><div class=\"big %s\">%zu</div>%s</a>", name, status_class((frig_photo_status)s),
            counts[s], name);
    }
    if (counts[FRIG_PHOTO_OK] > used)
        put(p, "<div class=\"card\"><div class=\"big\">%zu</div>usable, not fitted</div>", counts[FRIG_PHOTO_OK] - used);
    put(p, "</section>\n");
    if (few_photos(r, have_rig, used))
        put(p, "<div class=\"note\"><b>Few photos:</b> only %zu photos were used for the rig. On synthetic subjects "
               "(docs/run.md, \"How many photos\") rigs from 4-8 used photos were half again as far from the truth as "
               "rigs from 20-30, and those from 9-19 came in between, nearer the latter. More photos of the person, from "
               "other angles and with other expressions, give a closer shape.</div>\n", used);
    if (have_rig && r->stop[0]) {
        put(p, "<p class=\"files\">No rig was exported: the run stopped before the export stage (the pictures below show "
               "the last rig a stage made, not an exported one). Every photo's fate: <a href=\"report.json\">report.json</a>."
               "</p>\n");
    } else if (have_rig) {
        char rel[4200], shapes[4200];
        relative(r->out, r->rig.glb, rel, sizeof rel);
        relative(r->out, r->rig.shapes, shapes, sizeof shapes);
        put(p, "<p class=\"files\">The rig: <a href=\"");
        put_url(p, rel);
        put(p, "\">");
        put_text(p, rel);
        put(p, "</a> (glTF 2.0, metres, ARKit-named morph targets) and <a href=\"");
        put_url(p, shapes);
        put(p, "/\">");
        put_text(p, shapes);
        put(p, "/</a> (one OBJ per shape, ICT's vertex order). Every photo's fate: <a href=\"report.json\">report.json</a>.</p>\n");
    }
}

static void section_rig(page *p, int have_rig, int stopped) {
    put(p, "<h2 id=\"rig\">The rig</h2>\n");
    if (!have_rig) {
        put(p, "<p class=\"muted\">No rig yet: the run stopped before the fit.</p>\n");
        return;
    }
    if (stopped)
        put(p, "<p class=\"muted\">Not exported (the run stopped): the last rig a stage made, shown for what it is.</p>\n");
    put(p, "<p class=\"muted\">Rendered by libfrig's own rasterizer with the materials the glTF carries: painted "
           "sclera, iris and lashes, ICT's eye overlays blended (export.eye_overlays), the face texture when the sfs stage "
           "wrote one, else clay.</p>\n<div class=\"hero\">");
    static const char *const views[3][2] = {
        {"report/neutral_front.png", "front"}, {"report/neutral_34.png", "three-quarter"}, {"report/neutral_side.png", "side"}};
    for (int i = 0; i < 3; i++)
        put(p, "<figure><img src=\"%s\" width=\"360\" height=\"400\" alt=\"neutral, %s\"><figcaption>neutral, %s</figcaption></figure>",
            views[i][0], views[i][1], views[i][1]);
    put(p, "</div>\n<h3>Every blendshape at weight 1</h3>\n<a href=\"report/expressions.png\"><img class=\"sheet\" "
           "src=\"report/expressions.png\" alt=\"contact sheet of the neutral and every blendshape\"></a>\n");
}

/* The sfs stage's curves: each photo's shading error (the median relative error |I - a S(n)| /
 * |a S(n)| over its skin, eq. 5.15's E), clouds kept and sfs_failed apart; and each cloud's RMS
 * distance to the personalized rig after retarget's correspondence. */
static void section_sfs_errors(page *p, const frig_photoset *set) {
    size_t n = set ? frig_photoset_count(set) : 0, nk = 0, nx = 0, nc = 0;
    double *kept = n ? malloc(sizeof(double) * n) : NULL, *failed = n ? malloc(sizeof(double) * n) : NULL;
    double *cloud = n ? malloc(sizeof(double) * n) : NULL;
    for (size_t i = 0; kept && failed && cloud && i < n; i++) {
        double e, rms;
        size_t px, in;
        if (frig_photoset_sfs_done(set, i) && frig_photoset_sfs_stats(set, i, &px, &in, &e) == FRIG_OK && isfinite(e)) {
            /* a photo that failed before its shading was solved has no error to show */
            if (frig_photoset_status(set, i) == FRIG_PHOTO_SFS_FAILED) {
                if (e > 0) failed[nx++] = 100 * e;
            }
            else if (frig_photoset_status(set, i) == FRIG_PHOTO_OK) kept[nk++] = 100 * e;
        }
        if (frig_photoset_retargeted(set, i) && frig_photoset_retarget_figures(set, i, NULL, &rms, NULL, NULL) == FRIG_OK &&
            isfinite(rms))
            cloud[nc++] = rms;
    }
    if (nk + nx) {
        series s[2] = {{"clouds kept", "#8bd17c", kept, nk}, {"sfs_failed", "#e0645a", failed, nx}};
        plot(p, "Shape-from-shading error per photo", "median shading error |I - a S(n)| / a S(n), %", s, 2, 0,
             "Each fitted photo's median relative error between its skin pixels and the shading the recovered depth, "
             "albedo and lighting synthesize (section 5.1); pixels above sfs.e_max are left out of its cloud.");
    } else {
        put(p, "<figure class=\"plot note\"><p><b>Shape-from-shading error</b></p><p class=\"muted\">No photo has "
               "shape-from-shading results: the run stopped before the sfs stage.</p></figure>");
    }
    if (nc) {
        series c[1] = {{"clouds", "#6fb3e0", cloud, nc}};
        plot(p, "Cloud distance to the personalized rig", "RMS distance of matched cloud points, mm", c, 1, 0,
             "Each photo's point cloud against the personalized rig drawn at the photo's weights, after the last "
             "retarget round (points farther than retarget.max_distance_mm are not matched).");
    }
    free(kept), free(failed), free(cloud);
}

/* OUT/overlays/sfs/STEM.jpg of photo i into rel when it exists; 0 when not. */
static int sfs_overlay_for(run_ctx *r, const frig_photoset *set, size_t i, char *rel, size_t size) {
    const char *photo = frig_photoset_path(set, i), *base = strrchr(photo, '/') ? strrchr(photo, '/') + 1 : photo;
    const char *dot = strrchr(base, '.');
    int stem = (int)(dot && dot != base ? (size_t)(dot - base) : strlen(base));
    char path[4200];
    struct stat st;
    snprintf(rel, size, "overlays/sfs/%.*s.jpg", stem, base);
    return frig_photoset_sfs_done(set, i) && stat(run_path(r, rel, path, sizeof path), &st) == 0;
}

/* The sfs and retarget stages: the albedo, the rigs before and after, and the photos' sfs
 * pictures (skin, synthesized shading, error, kept region), the lowest-error ones first. */
static void section_shape(page *p, run_ctx *r, const frig_photoset *set) {
    char path[4200];
    struct stat st;
    int albedo = stat(run_path(r, "textures/albedo.png", path, sizeof path), &st) == 0;
    int rigs = stat(run_path(r, "overlays/retarget/rigs.png", path, sizeof path), &st) == 0;
    size_t n = set ? frig_photoset_count(set) : 0, shown = 0, *order = n ? malloc(sizeof(size_t) * n) : NULL;
    double *err = n ? malloc(sizeof(double) * n) : NULL;
    char rel[4200];
    for (size_t i = 0; order && err && i < n; i++) {
        double e;
        if (frig_photoset_status(set, i) != FRIG_PHOTO_OK || !sfs_overlay_for(r, set, i, rel, sizeof rel) ||
            frig_photoset_sfs_stats(set, i, NULL, NULL, &e))
            continue;
        size_t k = shown++;
        for (; k > 0 && err[k - 1] > e; k--) err[k] = err[k - 1], order[k] = order[k - 1]; /* by error, stable */
        err[k] = e, order[k] = i;
    }
    put(p, "<h2 id=\"shape\">The person's own shape</h2>\n");
    if (!albedo && !rigs && !shown) {
        put(p, "<p class=\"muted\">No shape from shading yet: the run stopped before the sfs stage, or no photo's shading "
               "could be read.</p>\n");
        free(order), free(err);
        return;
    }
    put(p, "<p class=\"muted\">The sfs stage (section 5.1) recovers a point cloud of the face from each photo's shading and "
           "the subject's albedo; the retarget stage (sections 5.2-5.3) deforms the rig onto the clouds, beyond the "
           "model's span, then refits every photo and recovers the clouds again (retarget.iterations rounds).</p>\n");
    char words[160];
    if (*cli_sfs_solve_words(set, words, sizeof words)) {
        put(p, "<p class=\"muted\">The shape all photos share came from ");
        put_text(p, words);
        put(p, " (docs/sfs.md: the full solve adds the views' agreement, the model's identity, each photo's "
               "registration and expression; the light one reads the shading alone).</p>\n");
    }
    put(p, "<div class=\"hero\">");
    if (rigs)
        put(p, "<figure><a href=\"overlays/retarget/rigs.png\"><img class=\"sheet\" src=\"overlays/retarget/rigs.png\" "
               "alt=\"the fit's rig and the personalized rig\"></a><figcaption>top: the fit's rig (the model's span); "
               "bottom: the personalized rig (rig.glb): neutral front and turned, jawOpen, smile, blink, brows up, "
               "pucker</figcaption></figure>");
    if (albedo)
        put(p, "<figure><a href=\"textures/albedo.png\"><img src=\"textures/albedo.png\" width=\"256\" height=\"256\" "
               "alt=\"the albedo texture\"></a><figcaption>textures/albedo.png: the skin's albedo in the model's UV "
               "layout, rig.glb's face texture</figcaption></figure>");
    put(p, "</div>\n");
    if (shown) {
        char dir[4200];
        cli_make_dir(r->env, run_path(r, "report/sfs", dir, sizeof dir));
        size_t show = shown < 12 ? shown : 12;
        put(p, "<h3>Shape from shading, photo by photo <span class=\"count\">%zu</span></h3>\n<p class=\"muted\">The "
               "%zu with the lowest shading error of the %zu with a cloud; every photo's is linked from its card below. Each picture: the "
               "photo's face, its skin, the shading synthesized from the recovered depth, the error, and the region kept "
               "in the cloud.</p>\n<div class=\"sfsgrid\">", shown, show, shown);
        for (size_t k = 0; k < show; k++) {
            size_t i = order[k];
            char src[4200], thumb[256], dst[4200];
            sfs_overlay_for(r, set, i, rel, sizeof rel);
            snprintf(thumb, sizeof thumb, "report/sfs/%zu.jpg", i);
            if (frig_image_save_thumbnail(r->env->ctx, run_path(r, rel, src, sizeof src), 2 * THUMB,
                                          run_path(r, thumb, dst, sizeof dst)))
                continue;
            const char *photo = frig_photoset_path(set, i), *base = strrchr(photo, '/') ? strrchr(photo, '/') + 1 : photo;
            put(p, "<figure><a href=\"");
            put_url(p, rel);
            put(p, "\"><img loading=\"lazy\" src=\"%s\" alt=\"", thumb);
            put_text(p, base);
            put(p, "\"></a><figcaption>%zu &middot; ", i);
            put_text(p, base);
            put(p, " &middot; error %.1f%%</figcaption></figure>", 100 * err[k]);
        }
        put(p, "</div>\n");
    }
    free(order), free(err);
}

static void section_errors(page *p, run_ctx *r, const frig_photoset *set) {
    put(p, "<h2 id=\"errors\">Error curves</h2>\n<p class=\"muted\">Cumulative distributions: the share of items "
           "(vertical) with at most the error on the horizontal axis; the dot marks the median. Errors are in %% of "
           "the distance between the eye centres, so photos of any size compare.</p>\n<div class=\"plots\">");
    size_t n = set ? frig_photoset_count(set) : 0;
    double *err = n ? malloc(sizeof(double) * 68 * n) : NULL, *eye = n ? malloc(sizeof(double) * n) : NULL;
    double *all = n ? malloc(sizeof(double) * 68 * n) : NULL, *jaw = n ? malloc(sizeof(double) * 17 * n) : NULL;
    double *inner = n ? malloc(sizeof(double) * 51 * n) : NULL, *rms = n ? malloc(sizeof(double) * n) : NULL;
    double *fe = n ? malloc(sizeof(double) * n) : NULL, *fd = n ? malloc(sizeof(double) * n) : NULL;
    size_t na = 0, nj = 0, ni = 0, nr = 0, nf = 0, nd = 0;
    int fit = 0;
    while (fit < run_stage_count && strcmp(run_stages[fit].name, "fit") != 0) fit++;
    int have = err && eye && all && jaw && inner && rms && fe && fd && fit < run_stage_count && r->results[fit].done &&
               run_load_model(r) == CLI_OK &&
               frig_fit_landmark_errors(r->env->ctx, r->model, set, err, eye) == FRIG_OK;
    for (size_t i = 0; have && i < n; i++) {
        if (!frig_photoset_fitted(set, i) || frig_photoset_status(set, i) != FRIG_PHOTO_OK || !(eye[i] > 0)) continue;
        for (int k = 0; k < 68; k++) {
            double e = 100.0 * err[68 * i + (size_t)k] / eye[i];
            if (!isfinite(e)) continue;
            all[na++] = e;
            if (k < 17) jaw[nj++] = e;
            else inner[ni++] = e;
        }
        rms[nr++] = 100.0 * frig_photoset_fit_error(set, i) / eye[i];
    }
    for (size_t i = 0; fe && fd && i < n; i++) {
        double e;
        int round;
        if (!frig_photoset_filter(set, i, &e, NULL, NULL, &round)) continue;
        if (round > 0) fd[nd++] = e;
        else fe[nf++] = e;
    }
    if (have) {
        series s[3] = {{"all 68", "#e8c16b", all, na}, {"jaw 0-16", "#e07b5a", jaw, nj}, {"inner 17-67", "#6fb3e0", inner, ni}};
        plot(p, "Landmark error: detected vs. the fitted model's", "error, % of the eye distance", s, 3, 0,
             "Each landmark of each used photo: the detector's point against the fitted face's. The jaw points slide along "
             "the silhouette, so they err most.");
        series f[1] = {{"photos", "#8bd17c", rms, nr}};
        plot(p, "Fit error per photo", "RMS landmark error, % of the eye distance", f, 1, 0,
             "Each used photo's RMS reprojection error after the final fit (jaw points weighted by fit.contour_weight).");
    } else {
        put(p, "<p class=\"muted\">No fit yet, so no landmark or fit errors.</p>");
    }
    if (nf + nd) {
        series f[2] = {{"kept", "#8bd17c", fe, nf}, {"dropped", "#e0645a", fd, nd}};
        plot(p, "Filter error (Algorithm 1)", "e = w_t RMSE(texture) + w_s shape error", f, 2, 0,
             "The robust-PCA reconstruction error of each checked photo; those above mu + omega sigma were dropped "
             "(filter.omega).");
    }
    section_sfs_errors(p, set);
    put(p, "</div>\n");
    free(err), free(eye), free(all), free(jaw), free(inner), free(rms), free(fe), free(fd);
}

/* How often the used photos show each fitted expression: the data a personalized blendshape is
 * learnt from (retarget); a shape no photo shows can only stay the template's. */
static void section_coverage(page *p, const frig_photoset *set) {
    int k = set ? frig_photoset_fit_expression_count(set) : 0;
    size_t n = set ? frig_photoset_count(set) : 0, used = 0;
    if (!k) return;
    double *w = malloc(sizeof(double) * (size_t)k), *top = calloc((size_t)k, sizeof(double));
    int *count = calloc((size_t)k, sizeof(int));
    if (!w || !top || !count) {
        free(w), free(top), free(count);
        return;
    }
    for (size_t i = 0; i < n; i++) {
        if (!frig_photoset_fitted(set, i) || frig_photoset_status(set, i) != FRIG_PHOTO_OK ||
            frig_photoset_fit_expression(set, i, w))
            continue;
        used++;
        for (int j = 0; j < k; j++) {
            count[j] += w[j] >= 0.3;
            if (w[j] > top[j]) top[j] = w[j];
        }
    }
    int shown = 0;
    for (int j = 0; j < k; j++) shown += count[j] > 0;
    put(p, "<h2 id=\"coverage\">What the photos show</h2>\n<p class=\"muted\">For each expression the fit uses: how "
           "many of the %zu used photos show it at weight 0.3 or more (bar) and the strongest weight seen. %d of %d "
           "are shown by at least one photo; the personalized blendshapes (the retarget stage) learn from these photos, "
           "and a shape no photo shows stays the template's.</p>\n<div class=\"cover\">",
        used, shown, k);
    for (int j = 0; j < k; j++) {
        double share = used ? (double)count[j] / (double)used : 0;
        put(p, "<div class=\"cov%s\"><span class=\"cname\">", count[j] ? "" : " none");
        put_text(p, frig_photoset_fit_expression_name(set, j));
        put(p, "</span><span class=\"bar\"><span style=\"width:%.1f%%\"></span></span><span class=\"cnum\">%d"
               " &middot; max %.2f</span></div>",
            100 * share, count[j], top[j]);
    }
    put(p, "</div>\n");
    free(w), free(top), free(count);
}

/* The photo's strongest fitted expressions ("jawOpen 0.62, eyeBlink_L 0.41"). */
static void put_top_expressions(page *p, const frig_photoset *set, size_t i) {
    int k = frig_photoset_fit_expression_count(set);
    double *w = k ? malloc(sizeof(double) * (size_t)k) : NULL;
    if (!w || frig_photoset_fit_expression(set, i, w)) {
        free(w);
        return;
    }
    int shown = 0;
    for (int t = 0; t < 3; t++) {
        int best = -1;
        for (int j = 0; j < k; j++)
            if (w[j] >= 0.2 && (best < 0 || w[j] > w[best])) best = j;
        if (best < 0) break;
        put(p, "%s", shown++ ? ", " : "<div class=\"expr\">");
        put_text(p, frig_photoset_fit_expression_name(set, best));
        put(p, " %.2f", w[best]);
        w[best] = -1;
    }
    if (shown) put(p, "</div>");
    else put(p, "<div class=\"expr\">neutral</div>");
    free(w);
}

static void section_stages(page *p, run_ctx *r, const frig_photoset *set) {
    put(p, "<h2 id=\"stages\">Stages: time and memory</h2>\n<table class=\"stages\"><tr><th>stage</th><th>what</th><th>"
           "this run</th><th class=\"num\">seconds</th><th class=\"num\">CPU seconds</th><th class=\"num\">peak memory</th>"
           "<th>result</th></tr>\n");
    double total = 0, cpu = 0, peak = 0;
    for (int i = 0; i < run_stage_count; i++) {
        const run_result *res = &r->results[i];
        if (!res->done && i != r->stage) continue;
        int current = i == r->stage && !res->done; /* the report itself */
        if (!current) total += res->seconds, cpu += res->cpu_seconds, peak = fmax(peak, res->peak_rss_mb);
        put(p, "<tr><td>%s</td><td>", run_stages[i].name);
        put_text(p, run_stages[i].what);
        if (current) {
            put(p, "</td><td>writing this page</td><td class=\"num\"></td><td class=\"num\"></td><td class=\"num\"></td><td></td>"
                   "</tr>\n");
            continue;
        }
        put(p, "</td><td>%s</td><td class=\"num\">%.1f</td><td class=\"num\">%.1f</td><td class=\"num\">%.0f MB</td><td>",
            res->ran ? "ran" : "kept", res->seconds, res->cpu_seconds, res->peak_rss_mb);
        put_text(p, res->summary);
        put(p, "</td></tr>\n");
    }
    size_t n = set ? frig_photoset_count(set) : 0;
    put(p, "<tr class=\"total\"><td>all</td><td>%zu photos, %d thread%s</td><td></td><td class=\"num\">%.1f</td>"
           "<td class=\"num\">%.1f</td><td class=\"num\">%.0f MB</td><td>",
        n, frig_ctx_threads(r->env->ctx), frig_ctx_threads(r->env->ctx) == 1 ? "" : "s", total, cpu, peak);
    int sfs = 0, retarget = 0;
    for (int i = 0; i < run_stage_count; i++) {
        sfs |= r->results[i].done && strcmp(run_stages[i].name, "sfs") == 0;
        retarget |= r->results[i].done && strcmp(run_stages[i].name, "retarget") == 0;
    }
    if (n && total > 0)
        put(p, "the paper's pipeline took about %.0f s for 100 photos; this run's stages, %.1f s per 100 photos (%.0fx "
               "faster%s)",
            PAPER_SECONDS, total * 100.0 / (double)n, PAPER_SECONDS / (total * 100.0 / (double)n),
            sfs && retarget ? ", sfs and retargeting included" : ", without sfs and retargeting, which this run did not reach");
    put(p, "</td></tr></table>\n<p class=\"muted\">Times are the last run of each stage (\"kept\": an earlier run whose "
           "options and inputs still hold). Peak memory is the process's resident peak during the stage. CPU seconds are user + system time of all "
           "threads: on a machine shared with other work the wall time grows, the CPU time much less.</p>\n");
}

static void section_photos(page *p, run_ctx *r, const frig_photoset *set) {
    size_t n = set ? frig_photoset_count(set) : 0;
    put(p, "<h2 id=\"photos\">Every photo</h2>\n<p class=\"muted\">The fitted face over each used photo (green: detected "
           "landmarks, red: the fit's); the detector's boxes and landmarks over the others. Click for the full size.</p>\n");
    char thumbs[4200];
    cli_make_dir(r->env, run_path(r, "report/thumbs", thumbs, sizeof thumbs));
    /* used photos first, then each other status in the enum's order */
    for (int pass = -1; pass < 32; pass++) {
        size_t count = 0;
        for (size_t i = 0; i < n; i++) {
            frig_photo_status s = frig_photoset_status(set, i);
            int used = s == FRIG_PHOTO_OK && frig_photoset_fitted(set, i);
            count += pass < 0 ? used : (int)s == pass && !used;
        }
        if (!count) continue;
        const char *name = pass < 0 ? "used" : frig_photo_status_name((frig_photo_status)pass);
        put(p, "<h3 id=\"%s\">%s <span class=\"count\">%zu</span> <span class=\"muted\">", name ? name : "other",
            pass < 0 ? "used" : name ? name : "other", count);
        if (pass >= 0) put_text(p, status_words((frig_photo_status)pass));
        put(p, "</span></h3>\n<div class=\"grid\">");
        for (size_t i = 0; i < n; i++) {
            frig_photo_status s = frig_photoset_status(set, i);
            int used = s == FRIG_PHOTO_OK && frig_photoset_fitted(set, i);
            if (pass < 0 ? !used : (int)s != pass || used) continue;
            char overlay[4200], thumb[256], src[4200], dst[4200];
            overlay_for(r, set, i, overlay, sizeof overlay);
            snprintf(thumb, sizeof thumb, "report/thumbs/%zu.jpg", i);
            int have = overlay[0] && frig_image_save_thumbnail(r->env->ctx, run_path(r, overlay, src, sizeof src), THUMB,
                                                               run_path(r, thumb, dst, sizeof dst)) == FRIG_OK;
            const char *path = frig_photoset_path(set, i), *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
            put(p, "<div class=\"photo %s\">", status_class(s));
            if (have) {
                put(p, "<a href=\"");
                put_url(p, overlay);
                put(p, "\"><img loading=\"lazy\" src=\"%s\" alt=\"", thumb);
                put_text(p, base);
                put(p, "\"></a>");
            } else {
                put(p, "<div class=\"noimg\">no picture</div>");
            }
            put(p, "<div class=\"name\" title=\"");
            put_text(p, path);
            put(p, "\">%zu &middot; ", i);
            put_text(p, base);
            put(p, "</div><div><span class=\"badge %s\">%s</span>", status_class(s), frig_photo_status_name(s));
            if (frig_photoset_fitted(set, i)) put(p, " fit %.2f px", frig_photoset_fit_error(set, i));
            if (frig_photoset_fit_in_joint(set, i)) put(p, ", joint");
            put(p, "</div>");
            if (frig_photoset_fitted(set, i)) put_top_expressions(p, set, i);
            char sfs[4200];
            size_t kept;
            double e;
            if (sfs_overlay_for(r, set, i, sfs, sizeof sfs) && frig_photoset_sfs_stats(set, i, NULL, &kept, &e) == FRIG_OK) {
                put(p, "<div class=\"sfs\"><a href=\"");
                put_url(p, sfs);
                put(p, "\">shape from shading</a>: %zu points, error %.1f%%</div>", kept, 100 * e);
            }
            const char *why = frig_photoset_reason(set, i);
            if (why && *why) {
                put(p, "<div class=\"why\">");
                put_text(p, why);
                put(p, "</div>");
            }
            put(p, "</div>");
        }
        put(p, "</div>\n");
    }
}

static const char style[] =
    "<style>\n"
    ":root{color-scheme:dark}body{margin:0;background:#17181b;color:#d9d9d6;font:15px/1.45 system-ui,-apple-system,"
    "'Segoe UI',sans-serif}\n"
    "main{max-width:1680px;margin:0 auto;padding:18px 28px 60px}h1{font-size:26px;margin:6px 0 2px}h2{margin:34px 0 6px;"
    "font-size:21px;border-bottom:1px solid #34363b;padding-bottom:4px}h3{font-size:16px;margin:22px 0 8px}\n"
    "a{color:#8cc4f0}nav a{margin-right:14px}.muted{color:#9a9b98}.files{margin:10px 0}\n"
    ".cards{display:flex;flex-wrap:wrap;gap:10px;margin:14px 0}.card{background:#222428;border:1px solid #303237;"
    "border-radius:8px;padding:10px 16px;min-width:110px;color:#c9cac6;text-decoration:none}\n"
    ".big{font-size:30px;font-weight:600;color:#f0f0ec}.big.ok{color:#8bd17c}.big.warn{color:#e8a95a}.big.bad{color:#e0645a}"
    ".big.none{color:#a5a7ab}.big.dup{color:#8aa6c8}\n"
    ".stop{background:#4a2323;border:1px solid #7a3a3a;border-radius:8px;padding:10px 14px;margin:12px 0}\n"
    ".note{background:#463c1e;border:1px solid #7a6a30;border-radius:8px;padding:10px 14px;margin:12px 0}\n"
    ".hero{display:flex;flex-wrap:wrap;gap:12px}figure{margin:0}figcaption{color:#9a9b98;font-size:13px;margin-top:4px}"
    "img.sheet{max-width:100%;border-radius:6px}\n"
    ".plots{display:flex;flex-wrap:wrap;gap:16px}.plot svg{background:#1e2023;border-radius:6px;max-width:100%;height:auto}"
    ".plot{max-width:520px}.plot.note{width:520px;background:#1e2023;border-radius:6px;padding:12px 16px;box-sizing:border-box}\n"
    "svg .bg{fill:#1e2023}svg .grid{stroke:#34363b;stroke-width:1}svg .tick{fill:#9a9b98;font-size:11px}"
    "svg .axis{fill:#b9bab6;font-size:12px}svg .title{fill:#e6e6e2;font-size:14px;font-weight:600}"
    "svg .legend{fill:#c9cac6;font-size:12px}\n"
    "table.stages{border-collapse:collapse;width:100%}table.stages td,table.stages th{border-bottom:1px solid #2c2e32;"
    "padding:6px 10px;text-align:left;vertical-align:top}table.stages .num{text-align:right;white-space:nowrap}"
    "tr.total td{font-weight:600;border-top:1px solid #45474c}\n"
    ".grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(232px,1fr));gap:10px}.photo{background:#202226;"
    "border:1px solid #2e3035;border-radius:8px;padding:6px;font-size:13px}.photo img{width:100%;height:auto;"
    "display:block;border-radius:4px;background:#111}\n"
    ".photo .name{white-space:nowrap;overflow:hidden;text-overflow:ellipsis;color:#e2e2de;margin:4px 0 2px}"
    ".photo .why{color:#a9aaa6;margin-top:3px}.noimg{height:120px;display:flex;align-items:center;justify-content:center;"
    "color:#777}\n"
    ".badge{display:inline-block;border-radius:4px;padding:0 6px;font-size:12px;font-weight:600}.badge.ok{background:#2f5a2a;"
    "color:#c9f0bf}.badge.warn{background:#6a4a1f;color:#ffd9a8}.badge.bad{background:#6a2a26;color:#ffc7c0}"
    ".badge.none{background:#3d3f44;color:#d0d1d4}.badge.dup{background:#2c3e56;color:#c8dcf5}\n"
    ".photo.warn{border-color:#5a4220}.photo.bad{border-color:#5a2622}.count{color:#9a9b98;font-weight:400}"
    ".photo .expr{color:#c8b98a;margin-top:2px}.photo .sfs{margin-top:2px}\n"
    ".sfsgrid{display:grid;grid-template-columns:repeat(auto-fill,minmax(300px,1fr));gap:10px}.sfsgrid img{width:100%;"
    "height:auto;display:block;border-radius:4px;background:#111}\n"
    ".cover{display:grid;grid-template-columns:repeat(auto-fill,minmax(330px,1fr));gap:3px 18px;font-size:13px}"
    ".cov{display:flex;align-items:center;gap:8px}.cov.none{color:#777}.cname{width:118px;white-space:nowrap;"
    "overflow:hidden;text-overflow:ellipsis}.bar{flex:1;height:9px;background:#2a2c30;border-radius:4px;overflow:hidden}"
    ".bar span{display:block;height:100%;background:#c8a95a}.cnum{width:108px;text-align:right;color:#9a9b98;white-space:nowrap}\n"
    "</style>\n";

int run_write_report(run_ctx *r) {
    cli_env *env = r->env;
    char dir[4200];
    if (cli_make_dir(env, run_path(r, "report", dir, sizeof dir))) return CLI_FAILED;
    frig_photoset *set = NULL;
    if (frig_photoset_load(env->ctx, r->out, &set)) set = NULL; /* no photos read yet: a short page */
    int have_rig = 0, rc = make_pictures(r, &have_rig);
    if (rc) {
        frig_photoset_free(set);
        return rc;
    }
    page p = {0};
    put(&p, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" "
            "content=\"width=device-width, initial-scale=1\"><title>frig run: ");
    put_text(&p, r->out);
    put(&p, "</title>\n%s</head><body><main>\n<h1>frig run report</h1><div class=\"muted\">", style);
    put_text(&p, r->out);
    put(&p, " &middot; libfrig %s</div>\n<nav><a href=\"#rig\">rig</a><a href=\"#shape\">own shape</a><a href=\"#errors\">error curves</a><a "
            "href=\"#coverage\">expressions</a><a href=\"#stages\">time and memory</a><a href=\"#photos\">photos</a></nav>\n",
        frig_version_string());
    section_summary(&p, r, set, have_rig);
    section_rig(&p, have_rig, r->stop[0] != 0);
    section_shape(&p, r, set);
    section_errors(&p, r, set);
    section_coverage(&p, set);
    section_stages(&p, r, set);
    section_photos(&p, r, set);
    put(&p, "</main></body></html>\n");
    char path[4200];
    run_path(r, "report.html", path, sizeof path);
    if (p.failed) rc = cli_fail_msg("run", "out of memory writing the report");
    else if (run_write_atomic(path, p.data, p.size)) rc = cli_fail_msg("run", "cannot write %s", path);
    if (rc == CLI_OK) {
        size_t used = used_photos(set);
        run_summary(r, "report.html: %zu photos shown, %zu used%s", set ? frig_photoset_count(set) : 0, used,
                    few_photos(r, have_rig, used) ? " (few for the shape: see the report's note)" : "");
    }
    free(p.data);
    frig_photoset_free(set);
    return rc;
}
