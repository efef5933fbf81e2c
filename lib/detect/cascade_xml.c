/* Reader for OpenCV's cascade XML (the layout opencv_traincascade writes: <cascade> with stageType,
 * featureType, width, height, featureParams, stages of weak trees and Haar <rects> or LBP <rect>
 * features), by a small XML tree builder of our own. Every index and count is checked, so a damaged
 * file is refused with a sentence instead of being evaluated. Reads what OpenCV 4.6's loader reads. */
#include <ctype.h>
#include <locale.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/cascade.h"
#include "io/file.h"

#define XML_MAX_DEPTH 64
#define CASCADE_MAX_FILE (256u << 20)
#define CASCADE_MAX_WINDOW 1024

/* ---- a minimal XML tree: elements with their content span, no entities, no CDATA ---- */

typedef struct xnode {
    const char *name;
    size_t name_len;
    const char *text; /* content between the start and end tag (a leaf's value) */
    size_t text_len;
    int first_child, next_sibling;
} xnode;

typedef struct xtree {
    xnode *nodes;
    int count, cap;
    const char *err; /* what was wrong, for the message */
    size_t err_at;   /* byte offset */
} xtree;

static int x_fail(xtree *t, const char *what, size_t at) {
    t->err = what;
    t->err_at = at;
    return -1;
}

static int x_add(xtree *t, const char *name, size_t len) {
    if (t->count == t->cap) {
        int cap = t->cap ? 2 * t->cap : 1024;
        xnode *n = realloc(t->nodes, (size_t)cap * sizeof *n);
        if (!n) return -2;
        t->nodes = n;
        t->cap = cap;
    }
    xnode *n = &t->nodes[t->count];
    n->name = name;
    n->name_len = len;
    n->text = NULL;
    n->text_len = 0;
    n->first_child = n->next_sibling = -1;
    return t->count++;
}

static int x_name_char(char c) {
    return isalnum((unsigned char)c) || c == '_' || c == ':' || c == '-' || c == '.';
}

/* Skip past 'end' starting at p; returns the offset after it or 0 when missing. */
static size_t x_skip_past(const char *s, size_t n, size_t p, const char *end) {
    size_t el = strlen(end);
    for (; p + el <= n; p++)
        if (memcmp(s + p, end, el) == 0) return p + el;
    return 0;
}

/* Parse s[0..n) into t; returns the root element's index, -1 on a syntax error, -2 out of memory. */
static int x_parse(xtree *t, const char *s, size_t n) {
    int stack[XML_MAX_DEPTH], last_child[XML_MAX_DEPTH];
    int depth = 0, root = -1;
    size_t p = 0;
    while (p < n) {
        const char *lt = memchr(s + p, '<', n - p);
        if (!lt) {
            for (; p < n; p++)
                if (!isspace((unsigned char)s[p]) && depth == 0) return x_fail(t, "text outside the root element", p);
            break;
        }
        if (depth == 0)
            for (size_t q = p; q < (size_t)(lt - s); q++)
                if (!isspace((unsigned char)s[q])) return x_fail(t, "text outside the root element", q);
        p = (size_t)(lt - s);
        if (n - p >= 4 && memcmp(s + p, "<!--", 4) == 0) {
            size_t e = x_skip_past(s, n, p + 4, "-->");
            if (!e) return x_fail(t, "unterminated comment", p);
            p = e;
        } else if (n - p >= 2 && s[p + 1] == '?') {
            size_t e = x_skip_past(s, n, p + 2, "?>");
            if (!e) return x_fail(t, "unterminated processing instruction", p);
            p = e;
        } else if (n - p >= 2 && s[p + 1] == '!') {
            if (n - p >= 9 && memcmp(s + p, "<![CDATA[", 9) == 0) return x_fail(t, "CDATA is not expected", p);
            size_t e = x_skip_past(s, n, p + 2, ">");
            if (!e) return x_fail(t, "unterminated declaration", p);
            p = e;
        } else if (n - p >= 2 && s[p + 1] == '/') {
            size_t q = p + 2, b = q;
            while (q < n && x_name_char(s[q])) q++;
            if (depth == 0) return x_fail(t, "end tag without a start tag", p);
            xnode *open = &t->nodes[stack[depth - 1]];
            if (q - b != open->name_len || memcmp(s + b, open->name, q - b) != 0)
                return x_fail(t, "end tag does not match its start tag", p);
            while (q < n && isspace((unsigned char)s[q])) q++;
            if (q >= n || s[q] != '>') return x_fail(t, "unterminated end tag", p);
            open->text_len = (size_t)(s + p - open->text);
            depth--;
            p = q + 1;
        } else {
            size_t q = p + 1, b = q;
            while (q < n && x_name_char(s[q])) q++;
            if (q == b) return x_fail(t, "bad tag", p);
            if (depth == 0 && root >= 0) return x_fail(t, "a second root element", p);
            if (depth == XML_MAX_DEPTH) return x_fail(t, "elements nested too deep", p);
            int id = x_add(t, s + b, q - b);
            if (id < 0) return id;
            if (depth > 0) {
                int parent = stack[depth - 1];
                if (last_child[depth - 1] < 0) t->nodes[parent].first_child = id;
                else t->nodes[last_child[depth - 1]].next_sibling = id;
                last_child[depth - 1] = id;
            } else {
                root = id;
            }
            /* attributes: name="value" or name='value', skipped */
            int empty = 0;
            for (;;) {
                while (q < n && isspace((unsigned char)s[q])) q++;
                if (q >= n) return x_fail(t, "unterminated start tag", p);
                if (s[q] == '>') break;
                if (s[q] == '/' && q + 1 < n && s[q + 1] == '>') {
                    empty = 1;
                    q++;
                    break;
                }
                if (s[q] == '"' || s[q] == '\'') {
                    const char *e = memchr(s + q + 1, s[q], n - q - 1);
                    if (!e) return x_fail(t, "unterminated attribute value", q);
                    q = (size_t)(e - s) + 1;
                } else if (x_name_char(s[q]) || s[q] == '=') {
                    q++;
                } else {
                    return x_fail(t, "bad character in a start tag", q);
                }
            }
            p = q + 1;
            t->nodes[id].text = s + p;
            if (!empty) {
                stack[depth] = id;
                last_child[depth] = -1;
                depth++;
            }
        }
    }
    if (depth > 0) return x_fail(t, "the file ends inside an element (truncated?)", n);
    if (root < 0) return x_fail(t, "no XML element", 0);
    return root;
}

static int x_is(const xtree *t, int id, const char *name) {
    size_t len = strlen(name);
    return t->nodes[id].name_len == len && memcmp(t->nodes[id].name, name, len) == 0;
}

static int x_child(const xtree *t, int id, const char *name) {
    if (id < 0) return -1;
    for (int c = t->nodes[id].first_child; c >= 0; c = t->nodes[c].next_sibling)
        if (x_is(t, c, name)) return c;
    return -1;
}

static int x_count_children(const xtree *t, int id) {
    int k = 0;
    for (int c = t->nodes[id].first_child; c >= 0; c = t->nodes[c].next_sibling) k++;
    return k;
}

/* ---- numbers in element text ---- */

typedef struct numreader {
    const char *p, *end;
} numreader;

static numreader x_numbers(const xtree *t, int id) {
    numreader r = {t->nodes[id].text, t->nodes[id].text + t->nodes[id].text_len};
    return r;
}

/* Next whitespace-separated number as a double (correctly rounded, whatever the C locale's decimal
 * point); 1 when read, 0 at the end, -1 when the token is not a finite number. */
static int x_next_number(numreader *r, double *v) {
    while (r->p < r->end && isspace((unsigned char)*r->p)) r->p++;
    if (r->p == r->end) return 0;
    const char *b = r->p;
    while (r->p < r->end && !isspace((unsigned char)*r->p)) r->p++;
    size_t len = (size_t)(r->p - b);
    char buf[64];
    if (len >= sizeof buf) return -1;
    memcpy(buf, b, len);
    buf[len] = 0;
    for (size_t i = 0; i < len; i++)
        if (!(isdigit((unsigned char)buf[i]) || buf[i] == '-' || buf[i] == '+' || buf[i] == '.' || buf[i] == 'e' ||
              buf[i] == 'E'))
            return -1;
    const char *dp = localeconv()->decimal_point;
    if (dp && dp[0] && dp[0] != '.' && !dp[1]) {
        char *dot = strchr(buf, '.');
        if (dot) *dot = dp[0];
    }
    char *endp;
    *v = strtod(buf, &endp);
    if (endp != buf + len || !isfinite(*v)) return -1;
    return 1;
}

static int x_next_int(numreader *r, int *v) {
    double d;
    int k = x_next_number(r, &d);
    if (k <= 0) return k;
    if (d != floor(d) || d < -2147483648.0 || d > 2147483647.0) return -1;
    *v = (int)d;
    return 1;
}

/* The element's whole text as exactly one number. */
static int x_scalar(const xtree *t, int id, double *v) {
    if (id < 0 || t->nodes[id].first_child >= 0) return -1;
    numreader r = x_numbers(t, id);
    double extra;
    if (x_next_number(&r, v) != 1 || x_next_number(&r, &extra) != 0) return -1;
    return 0;
}

static int x_text_is(const xtree *t, int id, const char *word) {
    if (id < 0) return 0;
    const char *s = t->nodes[id].text, *e = s + t->nodes[id].text_len;
    while (s < e && isspace((unsigned char)*s)) s++;
    while (e > s && isspace((unsigned char)e[-1])) e--;
    return (size_t)(e - s) == strlen(word) && memcmp(s, word, (size_t)(e - s)) == 0;
}

/* ---- the cascade ---- */

typedef struct reader {
    frig_ctx *ctx;
    const char *name;
    xtree *t;
} reader;

#define CORRUPT(rd, ...) fr_error((rd)->ctx, FRIG_ERR_CORRUPT, __VA_ARGS__)

void fr_cascade_free(fr_cascade *c) {
    if (!c) return;
    free(c->stages);
    free(c->trees);
    free(c->nodes);
    free(c->leaves);
    free(c->subsets);
    free(c->haar);
    free(c->lbp);
    free(c);
}

static frig_status read_int_field(reader *rd, int parent, const char *field, int lo, int hi, int *v) {
    double d;
    int id = x_child(rd->t, parent, field);
    if (id < 0) return CORRUPT(rd, "%s: cascade has no <%s>", rd->name, field);
    if (x_scalar(rd->t, id, &d) != 0 || d != floor(d) || d < lo || d > hi)
        return CORRUPT(rd, "%s: <%s> should be a whole number from %d to %d", rd->name, field, lo, hi);
    *v = (int)d;
    return FRIG_OK;
}

/* First pass over <stages>: count trees, nodes and leaves so that every array is allocated once. */
static frig_status count_stages(reader *rd, int stages_id, int node_step, fr_cascade *c) {
    const xtree *t = rd->t;
    long ntrees = 0, nnodes = 0, nleaves = 0;
    int si = 0;
    for (int s = t->nodes[stages_id].first_child; s >= 0; s = t->nodes[s].next_sibling, si++) {
        int weaks = x_child(t, s, "weakClassifiers");
        if (weaks < 0 || t->nodes[weaks].first_child < 0)
            return CORRUPT(rd, "%s: stage %d has no weak classifiers", rd->name, si);
        for (int w = t->nodes[weaks].first_child; w >= 0; w = t->nodes[w].next_sibling) {
            int in = x_child(t, w, "internalNodes"), lv = x_child(t, w, "leafValues");
            if (in < 0 || lv < 0)
                return CORRUPT(rd, "%s: stage %d has a weak classifier without internalNodes or leafValues",
                               rd->name, si);
            numreader r = x_numbers(t, in);
            double d;
            long k = 0;
            int got;
            while ((got = x_next_number(&r, &d)) == 1) k++;
            if (got < 0) return CORRUPT(rd, "%s: stage %d: internalNodes holds something not a number", rd->name, si);
            if (k == 0 || k % node_step != 0)
                return CORRUPT(rd, "%s: stage %d: internalNodes has %ld numbers, not a multiple of %d", rd->name, si, k,
                               node_step);
            ntrees++;
            nnodes += k / node_step;
            nleaves += k / node_step + 1;
            if (ntrees > 1000000 || nnodes > 10000000)
                return CORRUPT(rd, "%s: implausibly many weak classifiers", rd->name);
        }
    }
    if (si == 0) return CORRUPT(rd, "%s: cascade has no stages", rd->name);
    c->nstages = si;
    c->ntrees = (int)ntrees;
    c->nnodes = (int)nnodes;
    c->nleaves = (int)nleaves;
    return FRIG_OK;
}

/* One weak tree: nodes "left right feature threshold|subset...", then nnodes + 1 leaves. */
static frig_status read_tree(reader *rd, int w, int si, int node_step, fr_cascade *c, int *node_at, int *leaf_at) {
    const xtree *t = rd->t;
    fr_cascade_tree *tree = &c->trees[c->ntrees];
    numreader r = x_numbers(t, x_child(t, w, "internalNodes"));
    int k = 0, v;
    double d;
    while (x_next_number(&r, &d) == 1) k++;
    int nn = k / node_step;
    tree->first_node = *node_at;
    tree->nnodes = nn;
    tree->first_leaf = *leaf_at;
    r = x_numbers(t, x_child(t, w, "internalNodes"));
    for (int i = 0; i < nn; i++) {
        fr_cascade_node *node = &c->nodes[*node_at + i];
        if (x_next_int(&r, &node->left) != 1 || x_next_int(&r, &node->right) != 1 ||
            x_next_int(&r, &node->feature) != 1)
            return CORRUPT(rd, "%s: stage %d: a tree node's left, right or feature is not a whole number", rd->name,
                           si);
        int kids[2] = {node->left, node->right};
        for (int j = 0; j < 2; j++)
            if ((kids[j] > 0 && (kids[j] <= i || kids[j] >= nn)) || (kids[j] <= 0 && -kids[j] > nn))
                return CORRUPT(rd, "%s: stage %d: tree node %d points to a missing node or leaf (%d)", rd->name, si,
                               i, kids[j]);
        if (node->feature < 0 || node->feature >= c->nfeatures)
            return CORRUPT(rd, "%s: stage %d: feature index %d is outside 0..%d", rd->name, si, node->feature,
                           c->nfeatures - 1);
        if (c->type == FR_CASCADE_LBP) {
            node->threshold = 0.f;
            for (int j = 0; j < FR_CASCADE_SUBSET_WORDS; j++) {
                if (x_next_int(&r, &v) != 1)
                    return CORRUPT(rd, "%s: stage %d: an LBP subset word is not a 32-bit integer", rd->name, si);
                c->subsets[(size_t)(*node_at + i) * FR_CASCADE_SUBSET_WORDS + j] = v;
            }
        } else {
            if (x_next_number(&r, &d) != 1) return CORRUPT(rd, "%s: stage %d: bad node threshold", rd->name, si);
            node->threshold = (float)d;
        }
    }
    numreader lr = x_numbers(t, x_child(t, w, "leafValues"));
    int nl = 0, got;
    while ((got = x_next_number(&lr, &d)) == 1) {
        if (nl == nn + 1)
            return CORRUPT(rd, "%s: stage %d: a tree of %d nodes has more than %d leaf values", rd->name, si, nn,
                           nn + 1);
        c->leaves[*leaf_at + nl++] = (float)d;
    }
    if (got < 0 || nl != nn + 1)
        return CORRUPT(rd, "%s: stage %d: a tree of %d nodes needs %d leaf values, found %d", rd->name, si, nn, nn + 1,
                       nl);
    if (nn > c->max_nodes_per_tree) c->max_nodes_per_tree = nn;
    *node_at += nn;
    *leaf_at += nn + 1;
    c->ntrees++;
    return FRIG_OK;
}

static frig_status read_stages(reader *rd, int stages_id, int node_step, fr_cascade *c) {
    const xtree *t = rd->t;
    int node_at = 0, leaf_at = 0, si = 0;
    c->ntrees = 0;
    for (int s = t->nodes[stages_id].first_child; s >= 0; s = t->nodes[s].next_sibling, si++) {
        fr_cascade_stage *st = &c->stages[si];
        double thr;
        if (x_scalar(t, x_child(t, s, "stageThreshold"), &thr) != 0)
            return CORRUPT(rd, "%s: stage %d has no readable stageThreshold", rd->name, si);
        st->threshold = (float)thr - 1e-5f;
        int weaks = x_child(t, s, "weakClassifiers");
        st->first_tree = c->ntrees;
        st->ntrees = x_count_children(t, weaks);
        int mw = x_child(t, s, "maxWeakCount");
        double d;
        if (mw >= 0 && (x_scalar(t, mw, &d) != 0 || d != st->ntrees))
            return CORRUPT(rd, "%s: stage %d says maxWeakCount is not its %d weak classifiers", rd->name, si,
                           st->ntrees);
        for (int w = t->nodes[weaks].first_child; w >= 0; w = t->nodes[w].next_sibling) {
            frig_status e = read_tree(rd, w, si, node_step, c, &node_at, &leaf_at);
            if (e) return e;
        }
    }
    return FRIG_OK;
}

static frig_status read_haar_feature(reader *rd, int f, int fi, fr_cascade *c) {
    const xtree *t = rd->t;
    fr_cascade_haar *h = &c->haar[fi];
    memset(h, 0, sizeof *h);
    int rects = x_child(t, f, "rects");
    if (rects < 0) return CORRUPT(rd, "%s: Haar feature %d has no <rects>", rd->name, fi);
    int tl = x_child(t, f, "tilted");
    double d = 0;
    if (tl >= 0 && (x_scalar(t, tl, &d) != 0 || (d != 0 && d != 1)))
        return CORRUPT(rd, "%s: Haar feature %d: <tilted> should be 0 or 1", rd->name, fi);
    h->tilted = d != 0;
    for (int r = t->nodes[rects].first_child; r >= 0; r = t->nodes[r].next_sibling) {
        if (h->nrects == 3) return CORRUPT(rd, "%s: Haar feature %d has more than 3 rectangles", rd->name, fi);
        fr_cascade_rect *q = &h->rect[h->nrects++];
        numreader nr = x_numbers(t, r);
        double wt, extra;
        if (x_next_int(&nr, &q->x) != 1 || x_next_int(&nr, &q->y) != 1 || x_next_int(&nr, &q->w) != 1 ||
            x_next_int(&nr, &q->h) != 1 || x_next_number(&nr, &wt) != 1 || x_next_number(&nr, &extra) != 0)
            return CORRUPT(rd, "%s: Haar feature %d: a rectangle is not \"x y w h weight\"", rd->name, fi);
        q->weight = (float)wt;
        /* the rectangle's corners must fall inside the window's integral image */
        int ok = q->w > 0 && q->h > 0 && q->y >= 0;
        if (h->tilted) ok = ok && q->x - q->h >= 0 && q->x + q->w <= c->win_w && q->y + q->w + q->h <= c->win_h;
        else ok = ok && q->x >= 0 && q->x + q->w <= c->win_w && q->y + q->h <= c->win_h;
        if (!ok)
            return CORRUPT(rd, "%s: Haar feature %d: rectangle %d %d %d %d leaves the %dx%d window", rd->name, fi,
                           q->x, q->y, q->w, q->h, c->win_w, c->win_h);
    }
    if (h->nrects == 0) return CORRUPT(rd, "%s: Haar feature %d has no rectangles", rd->name, fi);
    if (h->tilted) c->has_tilted = 1;
    return FRIG_OK;
}

static frig_status read_lbp_feature(reader *rd, int f, int fi, fr_cascade *c) {
    fr_cascade_lbp *l = &c->lbp[fi];
    int rect = x_child(rd->t, f, "rect");
    if (rect < 0) return CORRUPT(rd, "%s: LBP feature %d has no <rect>", rd->name, fi);
    numreader nr = x_numbers(rd->t, rect);
    int extra;
    if (x_next_int(&nr, &l->x) != 1 || x_next_int(&nr, &l->y) != 1 || x_next_int(&nr, &l->w) != 1 ||
        x_next_int(&nr, &l->h) != 1 || x_next_int(&nr, &extra) != 0)
        return CORRUPT(rd, "%s: LBP feature %d: <rect> is not \"x y w h\"", rd->name, fi);
    if (l->x < 0 || l->y < 0 || l->w <= 0 || l->h <= 0 || l->x + 3 * l->w > c->win_w || l->y + 3 * l->h > c->win_h)
        return CORRUPT(rd, "%s: LBP feature %d: blocks %d %d %d %d leave the %dx%d window", rd->name, fi, l->x, l->y,
                       l->w, l->h, c->win_w, c->win_h);
    return FRIG_OK;
}

static frig_status read_features(reader *rd, int feats, fr_cascade *c) {
    const xtree *t = rd->t;
    int fi = 0;
    for (int f = t->nodes[feats].first_child; f >= 0; f = t->nodes[f].next_sibling, fi++) {
        frig_status e = c->type == FR_CASCADE_HAAR ? read_haar_feature(rd, f, fi, c) : read_lbp_feature(rd, f, fi, c);
        if (e) return e;
    }
    return FRIG_OK;
}

/* The header fields: types, window size, categories. */
static frig_status read_header(reader *rd, int top, fr_cascade *c, int *ncat) {
    const xtree *t = rd->t;
    int st = x_child(t, top, "stageType"), ft = x_child(t, top, "featureType");
    if (st < 0 && x_child(t, top, "size") >= 0)
        return fr_error(rd->ctx, FRIG_ERR_UNSUPPORTED,
                        "%s: old-format Haar cascade (opencv-haar-classifier) is not supported; use one written by "
                        "opencv_traincascade (all of Debian's face cascades are)",
                        rd->name);
    if (st < 0 || ft < 0) return CORRUPT(rd, "%s: not an OpenCV cascade (no stageType or featureType)", rd->name);
    if (!x_text_is(t, st, "BOOST")) return CORRUPT(rd, "%s: stageType is not BOOST", rd->name);
    if (x_text_is(t, ft, "HAAR")) c->type = FR_CASCADE_HAAR;
    else if (x_text_is(t, ft, "LBP")) c->type = FR_CASCADE_LBP;
    else if (x_text_is(t, ft, "HOG"))
        return fr_error(rd->ctx, FRIG_ERR_UNSUPPORTED, "%s: HOG cascades are not supported (nor by OpenCV 4)",
                        rd->name);
    else return CORRUPT(rd, "%s: unknown featureType", rd->name);
    frig_status e = read_int_field(rd, top, "width", 3, CASCADE_MAX_WINDOW, &c->win_w);
    if (!e) e = read_int_field(rd, top, "height", 3, CASCADE_MAX_WINDOW, &c->win_h);
    if (e) return e;
    int fp = x_child(t, top, "featureParams");
    if (fp < 0) return CORRUPT(rd, "%s: cascade has no <featureParams>", rd->name);
    e = read_int_field(rd, fp, "maxCatCount", 0, 1 << 20, ncat);
    if (e) return e;
    if (c->type == FR_CASCADE_HAAR && *ncat != 0)
        return CORRUPT(rd, "%s: a Haar cascade with maxCatCount %d (should be 0)", rd->name, *ncat);
    if (c->type == FR_CASCADE_LBP && *ncat != 256)
        return CORRUPT(rd, "%s: an LBP cascade with maxCatCount %d (should be 256)", rd->name, *ncat);
    return FRIG_OK;
}

static frig_status build(reader *rd, int root, fr_cascade *c) {
    const xtree *t = rd->t;
    /* OpenCV reads the first top-level node under <opencv_storage>, whatever its name */
    if (!x_is(t, root, "opencv_storage") || t->nodes[root].first_child < 0)
        return CORRUPT(rd, "%s: not an OpenCV storage file (no <opencv_storage> with a cascade)", rd->name);
    int top = t->nodes[root].first_child, ncat = 0;
    frig_status e = read_header(rd, top, c, &ncat);
    if (e) return e;
    int node_step = 3 + (ncat > 0 ? (ncat + 31) / 32 : 1);
    int stages = x_child(t, top, "stages"), feats = x_child(t, top, "features");
    if (stages < 0) return CORRUPT(rd, "%s: cascade has no <stages>", rd->name);
    if (feats < 0 || t->nodes[feats].first_child < 0) return CORRUPT(rd, "%s: cascade has no <features>", rd->name);
    c->nfeatures = x_count_children(t, feats);
    e = count_stages(rd, stages, node_step, c);
    if (e) return e;
    int sn = x_child(t, top, "stageNum");
    double d;
    if (sn >= 0 && (x_scalar(t, sn, &d) != 0 || d != c->nstages))
        return CORRUPT(rd, "%s: stageNum does not match the %d stages present", rd->name, c->nstages);
    c->stages = calloc((size_t)c->nstages, sizeof *c->stages);
    c->trees = calloc((size_t)c->ntrees, sizeof *c->trees);
    c->nodes = calloc((size_t)c->nnodes, sizeof *c->nodes);
    c->leaves = calloc((size_t)c->nleaves, sizeof *c->leaves);
    if (c->type == FR_CASCADE_LBP) {
        c->subsets = calloc((size_t)c->nnodes * FR_CASCADE_SUBSET_WORDS, sizeof *c->subsets);
        c->lbp = calloc((size_t)c->nfeatures, sizeof *c->lbp);
    } else {
        c->haar = calloc((size_t)c->nfeatures, sizeof *c->haar);
    }
    if (!c->stages || !c->trees || !c->nodes || !c->leaves || (!c->haar && !c->lbp) ||
        (c->type == FR_CASCADE_LBP && !c->subsets))
        return fr_nomem(rd->ctx, rd->name);
    e = read_features(rd, feats, c);
    if (!e) e = read_stages(rd, stages, node_step, c);
    return e;
}

frig_status fr_cascade_parse(frig_ctx *ctx, const char *name, const char *text, size_t size, fr_cascade **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_cascade_parse: NULL output");
    *out = NULL;
    if (!text) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_cascade_parse: NULL text");
    if (!name) name = "cascade";
    xtree t = {0};
    int root = x_parse(&t, text, size);
    if (root == -2) {
        free(t.nodes);
        return fr_nomem(ctx, name);
    }
    if (root < 0) {
        frig_status e = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: not well-formed XML at byte %zu: %s", name, t.err_at,
                                 t.err);
        free(t.nodes);
        return e;
    }
    fr_cascade *c = calloc(1, sizeof *c);
    if (!c) {
        free(t.nodes);
        return fr_nomem(ctx, name);
    }
    reader rd = {ctx, name, &t};
    frig_status e = build(&rd, root, c);
    free(t.nodes);
    if (e) {
        fr_cascade_free(c);
        return e;
    }
    *out = c;
    return FRIG_OK;
}

frig_status fr_cascade_load(frig_ctx *ctx, const char *path, fr_cascade **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_cascade_load: NULL output");
    *out = NULL;
    if (!path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_cascade_load: NULL path");
    unsigned char *data = NULL;
    size_t size = 0;
    frig_status e = fr_read_file(ctx, path, CASCADE_MAX_FILE, &data, &size);
    if (e) return e;
    e = fr_cascade_parse(ctx, path, (const char *)data, size, out);
    free(data);
    return e;
}
