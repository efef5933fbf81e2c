/* Merging of overlapping raw detections as OpenCV's groupRectangles: windows whose four edges agree
 * within eps * (mean of the smaller sides) join one class (transitively, like cv::partition); a class
 * of more than min_neighbors windows gives its average box, unless it lies inside a stronger box. */
#include <math.h>
#include <stdlib.h>

#include "detect/cascade.h"

static int similar(const fr_cascade_box *a, const fr_cascade_box *b, double eps) {
    double delta = eps * ((a->w < b->w ? a->w : b->w) + (a->h < b->h ? a->h : b->h)) * 0.5;
    return abs(a->x - b->x) <= delta && abs(a->y - b->y) <= delta && abs(a->x + a->w - b->x - b->w) <= delta &&
           abs(a->y + a->h - b->y - b->h) <= delta;
}

static size_t find_root(size_t *parent, size_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* Class of every box, numbered by first appearance (cv::partition's numbering); returns the count. */
static size_t partition(const fr_cascade_box *boxes, size_t n, double eps, size_t *parent, size_t *label) {
    for (size_t i = 0; i < n; i++) parent[i] = i;
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++) {
            if (!similar(&boxes[i], &boxes[j], eps)) continue;
            size_t a = find_root(parent, i), b = find_root(parent, j);
            if (a != b) parent[a > b ? a : b] = a < b ? a : b;
        }
    size_t nclasses = 0;
    for (size_t i = 0; i < n; i++) label[i] = (size_t)-1;
    for (size_t i = 0; i < n; i++) {
        size_t r = find_root(parent, i);
        if (label[r] == (size_t)-1) label[r] = nclasses++;
        label[i] = label[r];
    }
    return nclasses;
}

typedef struct group_acc {
    long x, y, w, h;
    int n;
    double weight;
    fr_cascade_box mean;
} group_acc;

long fr_cascade_group(fr_cascade_box *boxes, size_t n, int min_neighbors, double eps) {
    if (min_neighbors <= 0 || n == 0) {
        for (size_t i = 0; i < n; i++) boxes[i].neighbors = 1;
        return (long)n;
    }
    size_t *parent = malloc(sizeof(size_t) * n), *label = malloc(sizeof(size_t) * n);
    group_acc *g = calloc(n, sizeof *g);
    if (!parent || !label || !g) {
        free(parent);
        free(label);
        free(g);
        return -1;
    }
    size_t nc = partition(boxes, n, eps, parent, label);
    for (size_t c = 0; c < nc; c++) g[c].weight = -HUGE_VAL;
    for (size_t i = 0; i < n; i++) {
        group_acc *a = &g[label[i]];
        a->x += boxes[i].x;
        a->y += boxes[i].y;
        a->w += boxes[i].w;
        a->h += boxes[i].h;
        a->n++;
        if (boxes[i].weight > a->weight) a->weight = boxes[i].weight;
    }
    for (size_t c = 0; c < nc; c++) { /* OpenCV: sum * (1.f / n) in float, rounded to nearest even */
        float s = 1.f / (float)g[c].n;
        fr_cascade_box *m = &g[c].mean;
        m->x = (int)lrintf((float)g[c].x * s);
        m->y = (int)lrintf((float)g[c].y * s);
        m->w = (int)lrintf((float)g[c].w * s);
        m->h = (int)lrintf((float)g[c].h * s);
        m->neighbors = g[c].n;
        m->weight = g[c].weight;
    }
    long out = 0;
    for (size_t i = 0; i < nc; i++) {
        const fr_cascade_box *r1 = &g[i].mean;
        int n1 = g[i].n;
        if (n1 <= min_neighbors) continue;
        size_t j;
        for (j = 0; j < nc; j++) { /* drop a box inside a box of more neighbours */
            int n2 = g[j].n;
            if (j == i || n2 <= min_neighbors) continue;
            const fr_cascade_box *r2 = &g[j].mean;
            int dx = (int)lrint(r2->w * eps), dy = (int)lrint(r2->h * eps);
            if (r1->x >= r2->x - dx && r1->y >= r2->y - dy && r1->x + r1->w <= r2->x + r2->w + dx &&
                r1->y + r1->h <= r2->y + r2->h + dy && (n2 > (n1 > 3 ? n1 : 3) || n1 < 3))
                break;
        }
        if (j == nc) boxes[out++] = *r1;
    }
    free(parent);
    free(label);
    free(g);
    return out;
}
