/* The cascade XML reader: small cascades written here (Haar with a tree and a tilted feature, LBP)
 * read back field by field; every kind of damage (wrong counts, indices, rectangles outside the
 * window, bad numbers, broken or truncated XML, old or HOG formats) refused with the right status
 * and a sentence naming the file; thousands of random mutations parsed (and, when accepted, run)
 * without a crash; every Debian cascade read. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/cascade.h"
#include "testing.h"

static frig_ctx *ctx;

static const char *HAAR =
    "<?xml version=\"1.0\"?>\n"
    "<!-- a comment -->\n"
    "<opencv_storage>\n"
    "<cascade type_id=\"opencv-cascade-classifier\"><stageType>BOOST</stageType>\n"
    "  <featureType>HAAR</featureType>\n"
    "  <height>6</height>\n"
    "  <width>6</width>\n"
    "  <stageParams>\n"
    "    <maxWeakCount>2</maxWeakCount></stageParams>\n"
    "  <featureParams>\n"
    "    <maxCatCount>0</maxCatCount></featureParams>\n"
    "  <stageNum>2</stageNum>\n"
    "  <stages>\n"
    "    <_>\n"
    "      <maxWeakCount>1</maxWeakCount>\n"
    "      <stageThreshold>-5.0e-01</stageThreshold>\n"
    "      <weakClassifiers>\n"
    "        <_>\n"
    "          <internalNodes>\n"
    "            0 -1 0 1.5e-01</internalNodes>\n"
    "          <leafValues>\n"
    "            -1. 1.</leafValues></_></weakClassifiers></_>\n"
    "    <_>\n"
    "      <maxWeakCount>2</maxWeakCount>\n"
    "      <stageThreshold>0.25</stageThreshold>\n"
    "      <weakClassifiers>\n"
    "        <_>\n"
    "          <internalNodes>\n"
    "            0 1 1 -2.5e-02 -1 -2 0 3.0e-02</internalNodes>\n"
    "          <leafValues>\n"
    "            0.5 -0.5 0.25</leafValues></_>\n"
    "        <_>\n"
    "          <internalNodes>\n"
    "            0 -1 1 7.5e-02</internalNodes>\n"
    "          <leafValues>\n"
    "            -0.125 0.375</leafValues></_></weakClassifiers></_></stages>\n"
    "  <features>\n"
    "    <_>\n"
    "      <rects>\n"
    "        <_>\n"
    "          0 0 6 3 -1.</_>\n"
    "        <_>\n"
    "          0 3 6 3 1.</_></rects></_>\n"
    "    <_>\n"
    "      <rects>\n"
    "        <_>\n"
    "          2 0 2 2 -1.</_>\n"
    "        <_>\n"
    "          3 1 1 1 2.</_></rects>\n"
    "      <tilted>1</tilted></_></features></cascade>\n"
    "</opencv_storage>\n";

static const char *LBP =
    "<?xml version=\"1.0\"?>\n"
    "<opencv_storage>\n"
    "<cascade>\n"
    "  <stageType>BOOST</stageType>\n"
    "  <featureType>LBP</featureType>\n"
    "  <height>6</height>\n"
    "  <width>7</width>\n"
    "  <stageParams><maxDepth>1</maxDepth><maxWeakCount>1</maxWeakCount></stageParams>\n"
    "  <featureParams><maxCatCount>256</maxCatCount><featSize>1</featSize></featureParams>\n"
    "  <stageNum>1</stageNum>\n"
    "  <stages>\n"
    "    <_>\n"
    "      <maxWeakCount>1</maxWeakCount>\n"
    "      <stageThreshold>-0.75</stageThreshold>\n"
    "      <weakClassifiers>\n"
    "        <_>\n"
    "          <internalNodes>\n"
    "            0 -1 0 -67130709 -21569 -1426120013 -1275125205 -21585 -16385 587145899\n"
    "            -24005</internalNodes>\n"
    "          <leafValues>\n"
    "            -0.65 0.89</leafValues></_></weakClassifiers></_></stages>\n"
    "  <features>\n"
    "    <_>\n"
    "      <rect>\n"
    "        1 0 2 2</rect></_></features></cascade>\n"
    "</opencv_storage>\n";

static frig_status parse(const char *text, size_t n, fr_cascade **out) {
    return fr_cascade_parse(ctx, "synthetic.xml", text, n, out);
}

static void check_haar_fields(void) {
    fr_cascade *c = NULL;
    CHECK(parse(HAAR, strlen(HAAR), &c) == FRIG_OK && c);
    if (!c) return;
    CHECK(c->type == FR_CASCADE_HAAR && c->win_w == 6 && c->win_h == 6);
    CHECK(c->nstages == 2 && c->ntrees == 3 && c->nnodes == 4 && c->nleaves == 7 && c->nfeatures == 2);
    CHECK(c->has_tilted == 1 && c->max_nodes_per_tree == 2);
    CHECK(c->stages[0].threshold == (float)-0.5 - 1e-5f && c->stages[1].threshold == 0.25f - 1e-5f);
    CHECK(c->stages[1].first_tree == 1 && c->stages[1].ntrees == 2);
    const fr_cascade_tree *t = &c->trees[1];
    CHECK(t->first_node == 1 && t->nnodes == 2 && t->first_leaf == 2);
    CHECK(c->nodes[1].left == 0 && c->nodes[1].right == 1 && c->nodes[1].feature == 1);
    CHECK(c->nodes[1].threshold == (float)-2.5e-02 && c->nodes[2].threshold == (float)3.0e-02);
    CHECK(c->nodes[2].left == -1 && c->nodes[2].right == -2 && c->nodes[2].feature == 0);
    CHECK(c->leaves[2] == 0.5f && c->leaves[3] == -0.5f && c->leaves[4] == 0.25f && c->leaves[6] == 0.375f);
    CHECK(c->haar[0].nrects == 2 && c->haar[0].tilted == 0 && c->haar[0].rect[1].y == 3 &&
          c->haar[0].rect[0].weight == -1.f && c->haar[0].rect[2].weight == 0.f);
    CHECK(c->haar[1].tilted == 1 && c->haar[1].rect[1].x == 3 && c->haar[1].rect[1].weight == 2.f);
    fr_cascade_free(c);
}

static void check_lbp_fields(void) {
    fr_cascade *c = NULL;
    CHECK(parse(LBP, strlen(LBP), &c) == FRIG_OK && c);
    if (!c) return;
    CHECK(c->type == FR_CASCADE_LBP && c->win_w == 7 && c->win_h == 6 && c->max_nodes_per_tree == 1);
    CHECK(c->nstages == 1 && c->ntrees == 1 && c->nfeatures == 1 && c->stages[0].threshold == -0.75f - 1e-5f);
    CHECK(c->subsets[0] == -67130709 && c->subsets[6] == 587145899 && c->subsets[7] == -24005);
    CHECK(c->leaves[0] == -0.65f && c->leaves[1] == 0.89f);
    CHECK(c->lbp[0].x == 1 && c->lbp[0].y == 0 && c->lbp[0].w == 2 && c->lbp[0].h == 2);
    fr_cascade_free(c);
}

/* 'text' with the first occurrence of 'from' replaced by 'to' (static buffer). */
static const char *edit(const char *text, const char *from, const char *to) {
    static char buf[8192];
    const char *at = strstr(text, from);
    if (!at) {
        fprintf(stderr, "test bug: '%s' not in the text\n", from);
        abort();
    }
    size_t pre = (size_t)(at - text);
    snprintf(buf, sizeof buf, "%.*s%s%s", (int)pre, text, to, at + strlen(from));
    return buf;
}

static void expect(const char *text, frig_status want, const char *what) {
    fr_cascade *c = (fr_cascade *)1;
    frig_status s = parse(text, strlen(text), &c);
    if (s != want || c != NULL || !strstr(frig_ctx_errmsg(ctx), "synthetic.xml")) {
        fprintf(stderr, "%s: status %d (want %d), message '%s'\n", what, s, want, frig_ctx_errmsg(ctx));
        test_failures++;
    }
    if (s == FRIG_OK) fr_cascade_free(c);
}

static void check_damage(void) {
    const frig_status C = FRIG_ERR_CORRUPT, U = FRIG_ERR_UNSUPPORTED;
    expect(edit(HAAR, "<stageNum>2", "<stageNum>3"), C, "stageNum");
    expect(edit(HAAR, "<maxWeakCount>1</maxWeakCount>", "<maxWeakCount>2</maxWeakCount>"), C, "maxWeakCount");
    expect(edit(HAAR, "-1. 1.</leaf", "-1.</leaf"), C, "too few leaves");
    expect(edit(HAAR, "-1. 1.</leaf", "-1. 1. 2.</leaf"), C, "too many leaves");
    expect(edit(HAAR, "0 -1 0 1.5e-01", "0 -1 2 1.5e-01"), C, "feature index");
    expect(edit(HAAR, "0 -1 0 1.5e-01", "0 -1 -1 1.5e-01"), C, "negative feature index");
    expect(edit(HAAR, "0 -1 0 1.5e-01", "0 -1 0 1.5e-01 3"), C, "node count");
    expect(edit(HAAR, "0 1 1 -2.5e-02", "0 5 1 -2.5e-02"), C, "missing child node");
    expect(edit(HAAR, "0 1 1 -2.5e-02", "0 -4 1 -2.5e-02"), C, "missing leaf");
    expect(edit(HAAR, "-1 -2 0 3.0e-02", "1 -2 0 3.0e-02"), C, "node pointing to itself");
    expect(edit(HAAR, "0 -1 0 1.5e-01", "0 -1 0.5 1.5e-01"), C, "fractional index");
    expect(edit(HAAR, "1.5e-01", "1.5x-01"), C, "bad number");
    expect(edit(HAAR, "1.5e-01", "nan"), C, "nan");
    expect(edit(HAAR, "1.5e-01", "1e999"), C, "infinite threshold");
    expect(edit(HAAR, "-5.0e-01</stageThreshold>", "</stageThreshold>"), C, "empty threshold");
    expect(edit(HAAR, "0 3 6 3 1.", "0 4 6 3 1."), C, "rect below the window");
    expect(edit(HAAR, "0 3 6 3 1.", "-1 3 6 3 1."), C, "rect left of the window");
    expect(edit(HAAR, "0 3 6 3 1.", "0 3 0 3 1."), C, "empty rect");
    expect(edit(HAAR, "2 0 2 2 -1.", "1 0 2 2 -1."), C, "tilted rect leaving the window");
    expect(edit(HAAR, "0 3 6 3 1.", "0 3 6 3"), C, "rect without weight");
    expect(edit(HAAR, "<_>\n          0 3 6 3 1.</_>",
                "<_>0 3 6 3 1.</_><_>0 3 6 3 1.</_><_>0 3 6 3 1.</_><_>0 3 6 3 1.</_>"),
           C, "four rects");
    expect(edit(HAAR, "<tilted>1", "<tilted>2"), C, "tilted flag");
    expect(edit(HAAR, "<height>6", "<height>0"), C, "zero height");
    expect(edit(HAAR, "<height>6", "<height>6.5"), C, "fractional height");
    expect(edit(HAAR, "<width>6</width>", ""), C, "no width");
    expect(edit(HAAR, "<maxCatCount>0", "<maxCatCount>256"), C, "Haar with categories");
    expect(edit(HAAR, "<stageType>BOOST", "<stageType>TREE"), C, "stage type");
    expect(edit(HAAR, "<featureType>HAAR", "<featureType>SURF"), C, "feature type");
    expect(edit(HAAR, "<featureType>HAAR", "<featureType>HOG"), U, "HOG");
    expect(edit(HAAR, "</stageThreshold>", "</stageThreshol>"), C, "mismatched end tag");
    expect(edit(HAAR, "<stages>", "<stages"), C, "broken start tag");
    expect(edit(HAAR, "type_id=\"opencv-cascade-classifier\"", "type_id=\"opencv"), C, "unterminated attribute");
    expect(edit(HAAR, "<!-- a comment -->", "<!-- a comment"), C, "unterminated comment");
    expect(edit(HAAR, "</opencv_storage>", "</opencv_storage><x/>"), C, "second root");
    expect(edit(HAAR, "</opencv_storage>", "</opencv_storage> trailing"), C, "text after the root");
    expect(edit(HAAR, "<weakClassifiers>", "<weakClassifiers><![CDATA[x]]>"), C, "CDATA");
    expect("", C, "empty");
    expect("   \n  ", C, "blank");
    expect("not xml at all", C, "not XML");
    expect("<opencv_storage></opencv_storage>", C, "empty storage");
    expect("<a><b></a></b>", C, "crossed tags");
    expect("<opencv_storage><cascade><stageType>BOOST</stageType></cascade></opencv_storage>", C, "no feature type");
    expect("<opencv_storage><cascade_x type_id=\"opencv-haar-classifier\"><size>20 20</size><stages/>"
           "</cascade_x></opencv_storage>",
           U, "old format");
    char deep[2 * 6 * 200 + 64] = "";
    for (int i = 0; i < 200; i++) strcat(deep, "<_>");
    expect(deep, C, "deep nesting");
    /* LBP specifics */
    expect(edit(LBP, "<maxCatCount>256", "<maxCatCount>255"), C, "LBP category count");
    expect(edit(LBP, "            -24005</internal", "</internal"), C, "LBP subset short");
    expect(edit(LBP, "587145899", "2147483648"), C, "LBP subset out of range");
    expect(edit(LBP, "1 0 2 2</rect>", "2 0 2 2</rect>"), C, "LBP blocks leave the window");
    expect(edit(LBP, "1 0 2 2</rect>", "1 0 2 2 2</rect>"), C, "LBP rect with 5 numbers");
    /* binary garbage */
    unsigned char junk[512];
    unsigned x = 12345;
    for (size_t i = 0; i < sizeof junk; i++) junk[i] = (unsigned char)((x = x * 1103515245u + 12345u) >> 16);
    fr_cascade *c = NULL;
    CHECK(parse((const char *)junk, sizeof junk, &c) == FRIG_ERR_CORRUPT && !c);
}

/* Every prefix of a good file short of its last element's end is refused. */
static void check_truncation(const char *text, size_t keep_from) {
    size_t n = strlen(text), bad = 0;
    const char *end = strstr(text, "</opencv_storage>");
    size_t full = (size_t)(end - text) + strlen("</opencv_storage>");
    for (size_t k = keep_from; k < full; k++) {
        fr_cascade *c = NULL;
        frig_status s = parse(text, k, &c);
        if (s != FRIG_ERR_CORRUPT || c) bad++;
        fr_cascade_free(c);
    }
    if (bad) fprintf(stderr, "%zu of %zu truncations were not refused\n", bad, full - keep_from);
    CHECK(bad == 0);
    (void)n;
}

/* Seeded random edits: parse must never crash; whatever it accepts must also run. */
static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint64_t rnd(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

static void fuzz(const char *text, int rounds) {
    static const char alphabet[] = "<>/_ -.0123456789eE\"=abc\n";
    size_t n = strlen(text);
    char *buf = malloc(n + 64);
    uint8_t img[40 * 30];
    for (size_t i = 0; i < sizeof img; i++) img[i] = (uint8_t)(rnd() >> 40);
    int accepted = 0;
    for (int r = 0; r < rounds; r++) {
        memcpy(buf, text, n + 1);
        size_t len = n;
        int edits = 1 + (int)(rnd() % 3);
        for (int e = 0; e < edits; e++) {
            size_t at = (size_t)(rnd() % len);
            switch (rnd() % 3) {
            case 0: buf[at] = alphabet[rnd() % (sizeof alphabet - 1)]; break;
            case 1: memmove(buf + at, buf + at + 1, len - at), len--; break; /* delete */
            default:                                                          /* duplicate a digit */
                if (len + 1 < n + 64 && buf[at] >= '0' && buf[at] <= '9') {
                    memmove(buf + at + 1, buf + at, len - at + 1);
                    len++;
                }
            }
        }
        fr_cascade *c = NULL;
        frig_status s = parse(buf, len, &c);
        CHECK((s == FRIG_OK) == (c != NULL));
        if (c) {
            accepted++;
            fr_cascade_box *b = NULL;
            size_t nb = 0;
            CHECK(fr_cascade_detect(ctx, c, img, 40, 30, 40, 1.1, 1, 0, 0, 0, 0, &b, &nb) == FRIG_OK);
            free(b);
            fr_cascade_free(c);
        }
    }
    printf("fuzz: %d of %d mutated files accepted (and run)\n", accepted, rounds);
    free(buf);
}

/* Every cascade Debian ships reads (the one old-format file is refused as such); cut copies do not. */
static int check_debian(void) {
    static const char *haar[] = {"eye", "eye_tree_eyeglasses", "frontalcatface", "frontalcatface_extended",
                                 "frontalface_alt", "frontalface_alt2", "frontalface_alt_tree",
                                 "frontalface_default", "fullbody", "lefteye_2splits", "lowerbody", "profileface",
                                 "righteye_2splits", "russian_plate_number", "smile", "upperbody"};
    static const char *lbp[] = {"frontalcatface", "frontalface", "frontalface_improved", "profileface",
                                "silverware"};
    char path[512];
    snprintf(path, sizeof path, "/usr/share/opencv4/haarcascades/haarcascade_frontalface_alt2.xml");
    if (!test_file_exists(path)) return 0;
    for (size_t i = 0; i < sizeof haar / sizeof *haar; i++) {
        snprintf(path, sizeof path, "/usr/share/opencv4/haarcascades/haarcascade_%s.xml", haar[i]);
        fr_cascade *c = NULL;
        frig_status s = fr_cascade_load(ctx, path, &c);
        if (s) fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        CHECK(s == FRIG_OK && c && c->type == FR_CASCADE_HAAR);
        fr_cascade_free(c);
    }
    for (size_t i = 0; i < sizeof lbp / sizeof *lbp; i++) {
        snprintf(path, sizeof path, "/usr/share/opencv4/lbpcascades/lbpcascade_%s.xml", lbp[i]);
        fr_cascade *c = NULL;
        frig_status s = fr_cascade_load(ctx, path, &c);
        if (s) fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        CHECK(s == FRIG_OK && c && c->type == FR_CASCADE_LBP && c->max_nodes_per_tree == 1);
        fr_cascade_free(c);
    }
    fr_cascade *c = NULL;
    CHECK(fr_cascade_load(ctx, "/usr/share/opencv4/haarcascades/haarcascade_licence_plate_rus_16stages.xml", &c) ==
              FRIG_ERR_UNSUPPORTED &&
          !c);
    CHECK(fr_cascade_load(ctx, "/usr/share/opencv4/haarcascades/haarcascade_frontalface_alt2.xml", &c) == FRIG_OK);
    if (c) CHECK(c->nstages == 20 && c->win_w == 20 && c->win_h == 20 && c->max_nodes_per_tree == 2 && !c->has_tilted);
    fr_cascade_free(c);
    CHECK(fr_cascade_load(ctx, "/usr/share/opencv4/haarcascades/haarcascade_frontalface_default.xml", &c) == FRIG_OK);
    if (c) CHECK(c->nstages == 25 && c->win_w == 24 && c->max_nodes_per_tree == 1);
    fr_cascade_free(c);
    CHECK(fr_cascade_load(ctx, "/nonexistent/cascade.xml", &c) == FRIG_ERR_NOT_FOUND && !c);

    /* 40 cuts through a real file */
    FILE *fp = fopen("/usr/share/opencv4/haarcascades/haarcascade_frontalface_alt2.xml", "rb");
    if (!fp) return 0;
    fseek(fp, 0, SEEK_END);
    long size = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *text = malloc((size_t)size);
    if (text && fread(text, 1, (size_t)size, fp) == (size_t)size) {
        int bad = 0;
        for (int k = 0; k < 40; k++) {
            size_t cut = (size_t)((double)size * (k + 0.5) / 41);
            c = NULL;
            if (fr_cascade_parse(ctx, "alt2-cut.xml", text, cut, &c) != FRIG_ERR_CORRUPT || c) bad++;
            if (!strstr(frig_ctx_errmsg(ctx), "alt2-cut.xml")) bad++;
            fr_cascade_free(c);
        }
        CHECK(bad == 0);
    }
    free(text);
    fclose(fp);
    return 1;
}

int main(void) {
    ctx = frig_ctx_create();
    check_haar_fields();
    check_lbp_fields();
    check_damage();
    check_truncation(HAAR, 0);
    check_truncation(LBP, 0);
    fuzz(HAAR, 3000);
    fuzz(LBP, 1500);
    int have_debian = check_debian();
    frig_ctx_free(ctx);
    if (!test_failures && !have_debian) return test_skip("opencv-data is not installed (/usr/share/opencv4)");
    return test_result("test_cascade_xml");
}
