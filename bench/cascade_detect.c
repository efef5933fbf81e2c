/* Face boxes from libfrig's cascade evaluator, printed like shared/tools/opencv_ref.py does
 * (one JSON object per image: boxes, neighbours, detector seconds), for side-by-side runs
 * against OpenCV. Images are read as stored (no EXIF rotation), gray as OpenCV's IMREAD_GRAYSCALE.
 * Use: cascade_detect [--cascade XML] [--scale 1.1] [--neighbors 3] [--min-size 30] IMAGE...
 * With --neighbors-list 1,2,3 the raw windows are found once and grouped with each threshold
 * ("by_neighbors" in the output; boxes are clipped after grouping, as OpenCV does). With --flip 1 the
 * image is mirrored left-right before detection and the boxes mapped back (the profile cascade
 * finds faces turned one way only). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "detect/cascade.h"
#include "frig/image.h"

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void mirror(frig_image *img) {
    int w = frig_image_width(img);
    for (int y = 0; y < frig_image_height(img); y++) {
        uint8_t *row = frig_image_pixels_mutable(img) + (size_t)y * frig_image_stride(img);
        for (int x = 0; x < w / 2; x++) {
            uint8_t t = row[x];
            row[x] = row[w - 1 - x];
            row[w - 1 - x] = t;
        }
    }
}

/* Group copies of the raw windows with each threshold; print {"k": [[x,y,w,h,neighbours],...], ...}. */
static void print_groups(const fr_cascade_box *raw, size_t n, const int *list, int nlist, int w, int h) {
    fr_cascade_box *tmp = malloc(sizeof *tmp * (n ? n : 1));
    printf(", \"by_neighbors\": {");
    for (int k = 0; k < nlist && tmp; k++) {
        memcpy(tmp, raw, sizeof *tmp * n);
        long m = fr_cascade_group(tmp, n, list[k], 0.2);
        printf("%s\"%d\": [", k ? ", " : "", list[k]);
        int first = 1;
        for (long j = 0; j < m; j++) {
            int x0 = tmp[j].x > 0 ? tmp[j].x : 0, y0 = tmp[j].y > 0 ? tmp[j].y : 0;
            int x1 = tmp[j].x + tmp[j].w < w ? tmp[j].x + tmp[j].w : w;
            int y1 = tmp[j].y + tmp[j].h < h ? tmp[j].y + tmp[j].h : h;
            if (x1 <= x0 || y1 <= y0) continue;
            printf("%s[%d, %d, %d, %d, %d]", first ? "" : ", ", x0, y0, x1 - x0, y1 - y0, tmp[j].neighbors);
            first = 0;
        }
        printf("]");
    }
    printf("}");
    free(tmp);
}

int main(int argc, char **argv) {
    const char *cascade_path = "/usr/share/opencv4/haarcascades/haarcascade_frontalface_alt2.xml";
    double scale = 1.1;
    int neighbors = 3, min_size = 30, i = 1, nlist = 0, list[16], flip = 0;
    for (; i < argc && strncmp(argv[i], "--", 2) == 0; i += 2) {
        if (i + 1 >= argc) break;
        if (!strcmp(argv[i], "--cascade")) cascade_path = argv[i + 1];
        else if (!strcmp(argv[i], "--scale")) scale = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--neighbors")) neighbors = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--min-size")) min_size = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--flip")) flip = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--neighbors-list"))
            for (char *p = argv[i + 1]; *p && nlist < 16; p += strspn(p, ","))
                list[nlist++] = (int)strtol(p, &p, 10);
        else {
            fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    frig_ctx *ctx = frig_ctx_create();
    fr_cascade *c = NULL;
    if (!ctx || fr_cascade_load(ctx, cascade_path, &c)) {
        fprintf(stderr, "%s\n", ctx ? frig_ctx_errmsg(ctx) : "out of memory");
        return 1;
    }
    double total = 0;
    int images = 0;
    for (; i < argc; i++) {
        frig_image *img = NULL;
        if (frig_image_load(ctx, argv[i], FRIG_LOAD_GRAY | FRIG_LOAD_IGNORE_ORIENTATION, &img)) {
            printf("{\"image\": \"%s\", \"error\": \"unreadable\"}\n", argv[i]);
            continue;
        }
        if (flip) mirror(img);
        fr_cascade_box *b = NULL;
        size_t n = 0;
        double t0 = now();
        frig_status s = fr_cascade_detect(ctx, c, frig_image_pixels(img), frig_image_width(img),
                                          frig_image_height(img), frig_image_stride(img), scale,
                                          nlist ? 0 : neighbors, min_size,
                                          min_size, 0, 0, &b, &n);
        double dt = now() - t0;
        for (size_t k = 0; flip && k < n; k++) b[k].x = frig_image_width(img) - b[k].x - b[k].w;
        total += dt;
        images++;
        if (s) {
            printf("{\"image\": \"%s\", \"error\": \"%s\"}\n", argv[i], frig_ctx_errmsg(ctx));
        } else {
            printf("{\"image\": \"%s\", \"width\": %d, \"height\": %d, \"boxes\": [", argv[i],
                   frig_image_width(img), frig_image_height(img));
            for (size_t k = 0; k < n; k++)
                printf("%s[%d, %d, %d, %d]", k ? ", " : "", b[k].x, b[k].y, b[k].w, b[k].h);
            printf("], \"neighbors\": [");
            for (size_t k = 0; k < n; k++) printf("%s%d", k ? ", " : "", b[k].neighbors);
            printf("], \"weights\": [");
            for (size_t k = 0; k < n; k++) printf("%s%.6f", k ? ", " : "", b[k].weight);
            printf("], \"seconds\": %.5f", dt);
            if (nlist) print_groups(b, n, list, nlist, frig_image_width(img), frig_image_height(img));
            printf("}\n");
        }
        free(b);
        frig_image_free(img);
    }
    fprintf(stderr, "total detector seconds %.3f for %d images\n", total, images);
    fr_cascade_free(c);
    frig_ctx_free(ctx);
    return 0;
}
