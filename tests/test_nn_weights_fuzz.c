/* Mutation test of the TensorFlow.js weights loader on a real file (face-api's 68-point
 * landmark net: an 8 kB manifest, a 350 kB shard): byte flips and truncations of the manifest,
 * truncations and extensions of the shard, edited shapes and names, each given to the parser
 * and the network's loader. Every mutant must give a status and a sentence (never a crash:
 * run under ASan), truncations must fail, a flipped shape or name must be caught. Then the file
 * loader: a missing shard, a shard path leaving the folder, a shard one byte short. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "nn/face_nets.h"
#include "nn/weights.h"
#include "testing.h"

static uint64_t next(uint64_t *s) {
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

/* Parse, then build the network: 0 when both succeed. */
static frig_status try_load(frig_ctx *ctx, const char *man, size_t mn, const unsigned char *bin, size_t bn) {
    fr_nn_weights *w = NULL;
    frig_status s = fr_nn_weights_parse(ctx, "mutant", man, mn, bin, bn, &w);
    if (s == FRIG_OK) {
        fr_landmark_net *net = NULL;
        s = fr_landmark_net_from(ctx, w, &net);
        fr_landmark_net_free(net);
        fr_nn_weights_free(w);
    }
    CHECK(s == FRIG_OK || frig_ctx_errmsg(ctx)[0] != 0);
    return s;
}

static void write_file(const char *dir, const char *name, const void *data, size_t n) {
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "wb");
    if (fp) fwrite(data, 1, n, fp), fclose(fp);
}

int main(void) {
    const char *dir = fr_face_models_dir(NULL);
    char mpath[4200], bpath[4200];
    snprintf(mpath, sizeof mpath, "%s/%s-weights_manifest.json", dir, FR_LANDMARK_MODEL);
    snprintf(bpath, sizeof bpath, "%s/%s.bin", dir, FR_LANDMARK_MODEL);
    size_t mn, bn;
    unsigned char *man = test_read_file(mpath, &mn), *bin = test_read_file(bpath, &bn);
    if (!man || !bin) {
        free(man), free(bin);
        return test_skip("no face-api weights (scripts/install-deps.sh installs them; or set FRIG_FACE_MODELS)");
    }
    frig_ctx *ctx = frig_ctx_create();
    CHECK(try_load(ctx, (const char *)man, mn, bin, bn) == FRIG_OK);
    uint64_t seed = 0x2545F4914F6CDD1DULL;
    int counts[4] = {0}, loaded[4] = {0}, statuses[16] = {0};
    char *m = malloc(mn + 1);
    unsigned char *b = malloc(bn + 16);
    for (int it = 0; it < 400; it++) {
        int kind = it % 4; /* 0: manifest flips, 1: manifest cut, 2: shard cut or grown, 3: shape / name edits */
        memcpy(m, man, mn);
        memcpy(b, bin, bn);
        size_t mlen = mn, blen = bn;
        if (kind == 0) {
            int flips = 1 + (int)(next(&seed) % 4);
            for (int f = 0; f < flips; f++) m[next(&seed) % mn] ^= (char)(1 + next(&seed) % 255);
        } else if (kind == 1) {
            mlen = (size_t)(next(&seed) % mn);
        } else if (kind == 2) {
            blen = next(&seed) % 2 ? (size_t)(next(&seed) % bn) : bn + 1 + (size_t)(next(&seed) % 16);
            if (blen > bn) memset(b + bn, 0, blen - bn);
        } else {
            /* change one digit inside a "shape" array, or one letter of a "name" */
            const char *key = next(&seed) % 2 ? "\"shape\"" : "\"name\"";
            int nth = (int)(next(&seed) % 40);
            char *p = m;
            for (int k = 0; k <= nth && p; k++) p = strstr(p + 1, key);
            if (p) {
                p += strlen(key);
                while (*p && !(key[1] == 's' ? (*p >= '0' && *p <= '9') : (*p >= 'a' && *p <= 'z'))) p++;
                if (key[1] == 's') *p = *p == '9' ? '7' : (char)(*p + 1);
                else *p = *p == 'z' ? 'y' : (char)(*p + 1);
            }
        }
        frig_ctx_clear_error(ctx);
        frig_status s = try_load(ctx, m, mlen, b, blen);
        statuses[s & 15]++;
        counts[kind]++;
        loaded[kind] += s == FRIG_OK;
        if (kind == 1 || kind == 2 || kind == 3) CHECK(s != FRIG_OK);
    }
    printf("mutants: %d manifest flips (%d loaded), %d manifest cuts, %d shard cuts/growths, %d shape/name edits "
           "(loaded: %d, %d, %d)\n",
           counts[0], loaded[0], counts[1], counts[2], counts[3], loaded[1], loaded[2], loaded[3]);
    printf("statuses: ok %d, corrupt %d, truncated %d, unsupported %d\n", statuses[FRIG_OK], statuses[FRIG_ERR_CORRUPT],
           statuses[FRIG_ERR_TRUNCATED], statuses[FRIG_ERR_UNSUPPORTED]);
    printf("last message: %s\n", frig_ctx_errmsg(ctx));

    /* The file loader. */
    const char *tmp = test_temp_dir("nn_weights_fuzz");
    write_file(tmp, FR_LANDMARK_MODEL "-weights_manifest.json", man, mn);
    fr_nn_weights *w = NULL;
    CHECK(fr_nn_weights_load(ctx, tmp, FR_LANDMARK_MODEL, &w) == FRIG_ERR_NOT_FOUND && w == NULL);
    CHECK(strstr(frig_ctx_errmsg(ctx), FR_LANDMARK_MODEL ".bin") != NULL);
    write_file(tmp, FR_LANDMARK_MODEL ".bin", bin, bn - 1);
    CHECK(fr_nn_weights_load(ctx, tmp, FR_LANDMARK_MODEL, &w) == FRIG_ERR_TRUNCATED && w == NULL);
    printf("one byte short: %s\n", frig_ctx_errmsg(ctx));
    write_file(tmp, FR_LANDMARK_MODEL ".bin", bin, bn);
    CHECK(fr_nn_weights_load(ctx, tmp, FR_LANDMARK_MODEL, &w) == FRIG_OK && w != NULL);
    fr_nn_weights_free(w);
    w = NULL;
    char *escaped = strstr((char *)man, FR_LANDMARK_MODEL ".bin");
    if (escaped) {
        memcpy(m, man, mn);
        memcpy(m + (escaped - (char *)man), "../", 3); /* "face_landmark..." -> "../e_landmark..." */
        write_file(tmp, FR_LANDMARK_MODEL "-weights_manifest.json", m, mn);
        CHECK(fr_nn_weights_load(ctx, tmp, FR_LANDMARK_MODEL, &w) == FRIG_ERR_CORRUPT && w == NULL);
        printf("shard outside the folder: %s\n", frig_ctx_errmsg(ctx));
    }
    CHECK(fr_nn_weights_load(ctx, "/nonexistent-folder", FR_LANDMARK_MODEL, &w) == FRIG_ERR_NOT_FOUND);
    fr_face_models *fm = NULL;
    CHECK(fr_face_models_load(ctx, "/nonexistent-folder", &fm) == FRIG_ERR_NOT_FOUND && fm == NULL);
    CHECK(strstr(frig_ctx_errmsg(ctx), "install-deps") != NULL);
    free(m), free(b), free(man), free(bin);
    frig_ctx_free(ctx);
    return test_result("test_nn_weights_fuzz");
}
