/* The imported ICT model for tests, cached in the build tree: test-tmp/model-cache/
 * ict.frigmodel, rebuilt when older than the library (under a lock, since tests run in
 * parallel; tests/scripts/model_fixture.sh shares the same file). */
#ifndef FRIG_MODEL_FIXTURE_H
#define FRIG_MODEL_FIXTURE_H

#include <fcntl.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <frig/frig.h>

#include "testing.h"

static inline const char *fixture_model_path(void) { return FRIG_BINARY_DIR "/test-tmp/model-cache/ict.frigmodel"; }

static inline int fixture_is_fresh(const char *path) {
    struct stat model, lib;
    if (stat(path, &model) != 0) return 0;
    if (stat(FRIG_BINARY_DIR "/libfrig.a", &lib) != 0) return 1;
    return model.st_mtime >= lib.st_mtime;
}

/* The ICT folder, or NULL when the shared data is missing. */
static inline const char *fixture_ict_dir(void) {
    static char dir[4096];
    snprintf(dir, sizeof dir, "%s", test_shared_path("ict-facekit"));
    char probe[4200];
    snprintf(probe, sizeof probe, "%s/generic_neutral_mesh.obj", dir);
    return test_file_exists(probe) ? dir : NULL;
}

/* Load the cached model (importing it first if needed); NULL when the data is missing or
 * something failed (a message is printed). */
static inline frig_model *fixture_model(frig_ctx *ctx) {
    const char *ict = fixture_ict_dir();
    if (!ict) return NULL;
    const char *path = fixture_model_path();
    if (system("mkdir -p '" FRIG_BINARY_DIR "/test-tmp/model-cache'") != 0) return NULL;
    int lock = open(FRIG_BINARY_DIR "/test-tmp/model-cache/lock", O_CREAT | O_RDWR, 0644);
    if (lock >= 0) flock(lock, LOCK_EX);
    frig_model *m = NULL;
    if (!fixture_is_fresh(path) || frig_model_load(ctx, path, &m) != FRIG_OK) {
        if (frig_model_import_ict(ctx, ict, &m) != FRIG_OK || frig_model_save(ctx, m, path) != FRIG_OK) {
            fprintf(stderr, "fixture: cannot import %s: %s\n", ict, frig_ctx_errmsg(ctx));
            frig_model_free(m);
            m = NULL;
        }
    }
    if (lock >= 0) close(lock);
    return m;
}

#endif
