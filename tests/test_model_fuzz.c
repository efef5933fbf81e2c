/* Mutation test of the model loader: random byte flips and truncations of a real model
 * file must give a status (never a crash, never OK with a damaged checksum); flips with a
 * repaired checksum exercise the count and index validation behind it. Run under ASan. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/container.h"
#include "io/crc32.h"
#include "model/model.h"
#include "model_fixture.h"
#include "testing.h"

static uint64_t next(uint64_t *s) {
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

static void repair_crc(unsigned char *b, size_t n) {
    static const unsigned char zero[4] = {0};
    fr_crc32 c;
    fr_crc32_init(&c);
    fr_crc32_update(&c, b, 40);
    fr_crc32_update(&c, zero, 4);
    fr_crc32_update(&c, b + 44, n - 44);
    uint32_t v = fr_crc32_final(&c);
    for (int i = 0; i < 4; i++) b[40 + i] = (unsigned char)(v >> (8 * i));
}

/* A loaded mutant must be usable: touch every index through the public API. */
static void use(frig_ctx *ctx, const frig_model *m) {
    int nv = frig_model_vertex_count(m);
    const int32_t *t = frig_model_triangles(m);
    long sum = 0;
    for (int i = 0; i < 3 * frig_model_triangle_count(m); i++) sum += t[i] < nv;
    float *x = malloc(sizeof *x * 3 * (size_t)nv);
    frig_model_eval(ctx, m, NULL, NULL, x);
    frig_rig *r = NULL;
    if (frig_rig_from_model(ctx, m, NULL, &r) == FRIG_OK) CHECK(frig_rig_vertex_count(r) == nv);
    frig_rig_free(r);
    free(x);
    CHECK(sum == 3L * frig_model_triangle_count(m));
}

/* Position inside the header, the section table, or a section's first bytes (where the
 * counts and indices are), so that repaired mutants reach the validation. */
static size_t structural_position(const unsigned char *b, size_t n, uint64_t *s) {
    uint32_t sections = (uint32_t)b[16] | (uint32_t)b[17] << 8;
    size_t table_end = 64 + 40 * (size_t)sections;
    if (next(s) % 2) return (size_t)(next(s) % table_end);
    const unsigned char *e = b + 64 + 40 * (next(s) % sections);
    uint64_t off = 0;
    for (int i = 7; i >= 0; i--) off = off << 8 | e[24 + i];
    size_t pos = (size_t)off + (size_t)(next(s) % 4096);
    return pos < n ? pos : n - 1;
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    frig_model *full = fixture_model(ctx);
    if (!full) {
        frig_ctx_free(ctx);
        return test_skip("no ICT-FaceKit model (../shared/ict-facekit) to mutate");
    }
    /* A real model file with 2 identity modes and 3 expressions keeps every section and
     * stays small enough for hundreds of loads under ASan. */
    unsigned char *image;
    size_t size;
    CHECK(fr_model_pack(ctx, full, 2, 3, &image, &size) == FRIG_OK);
    unsigned char *copy = malloc(size);
    memcpy(copy, image, size);
    frig_model *m = NULL;
    CHECK(fr_model_from_image(ctx, "small", copy, size, &m) == FRIG_OK);
    frig_model_free(m);

    uint64_t seed = 0x9E3779B97F4A7C15ULL;
    int raw = 0, raw_ok = 0, trunc = 0, repaired = 0, repaired_ok = 0;
    int statuses[16] = {0};
    for (int it = 0; it < 600; it++) {
        unsigned char *b = malloc(size);
        memcpy(b, image, size);
        size_t n = size;
        int kind = it % 3; /* 0: flips, 1: truncation, 2: flips with a repaired checksum */
        if (kind == 1) {
            n = (size_t)(next(&seed) % size);
        } else {
            int flips = 1 + (int)(next(&seed) % 8);
            for (int f = 0; f < flips; f++) {
                size_t pos = kind == 2 ? structural_position(image, size, &seed) : (size_t)(next(&seed) % size);
                unsigned char x = (unsigned char)(1 + next(&seed) % 255);
                b[pos] ^= x;
            }
            if (kind == 2) repair_crc(b, n);
        }
        frig_status s = fr_model_from_image(ctx, "mutant", b, n, &m); /* takes b over */
        statuses[s & 15]++;
        if (kind == 0) raw++, raw_ok += s == FRIG_OK;
        if (kind == 1) trunc++;
        if (kind == 2) {
            repaired++;
            if (s == FRIG_OK) repaired_ok++, use(ctx, m);
        }
        CHECK(!(s == FRIG_OK && kind != 2)); /* a damaged checksum or size never loads */
        frig_model_free(m);
        m = NULL;
    }
    CHECK(raw_ok == 0);
    printf("mutations: %d byte-flip (%d loaded), %d truncations, %d checksum-repaired (%d loaded and used)\n", raw,
           raw_ok, trunc, repaired, repaired_ok);
    printf("statuses: ok %d, corrupt %d, truncated %d, unsupported %d\n", statuses[FRIG_OK], statuses[FRIG_ERR_CORRUPT],
           statuses[FRIG_ERR_TRUNCATED], statuses[FRIG_ERR_UNSUPPORTED]);
    CHECK(repaired_ok < repaired); /* the validation behind the checksum does reject */

    /* The full-size file: a few truncations and flips. */
    unsigned char *big;
    size_t bsize;
    CHECK(fr_model_pack(ctx, full, frig_model_identity_count(full), frig_model_expression_count(full), &big, &bsize) ==
          FRIG_OK);
    for (int it = 0; it < 6; it++) {
        unsigned char *b = malloc(bsize);
        memcpy(b, big, bsize);
        size_t n = bsize;
        if (it % 2) n = (size_t)(next(&seed) % bsize);
        else b[next(&seed) % bsize] ^= 0x40;
        frig_status s = fr_model_from_image(ctx, "big mutant", b, n, &m);
        CHECK(s != FRIG_OK && m == NULL);
        frig_model_free(m);
        m = NULL;
    }
    printf("last message: %s\n", frig_ctx_errmsg(ctx));
    free(big);
    free(image);
    frig_model_free(full);
    frig_ctx_free(ctx);
    return test_result("test_model_fuzz");
}
