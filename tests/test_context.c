/* The context: version, statuses, parameters with bounds, errors, cancel, progress. */
#include <string.h>

#include "core/context.h"
#include "testing.h"

static int progress_calls;
static size_t last_done;
static void on_progress(void *user, const char *stage, size_t done, size_t total) {
    (void)user;
    (void)stage;
    if (done < last_done || done > total) test_failures++;
    last_done = done;
    progress_calls++;
}

int main(void) {
    CHECK(frig_version_number() == FRIG_VERSION_NUMBER);
    CHECK(strcmp(frig_version_string(), FRIG_VERSION_STRING) == 0);
    for (int s = 0; s <= FRIG_ERR_INTERNAL; s++) CHECK(frig_strerror((frig_status)s)[0] != 0);

    frig_ctx *ctx = frig_ctx_create();
    CHECK(frig_ctx_status(ctx) == FRIG_OK && frig_ctx_errmsg(ctx)[0] == 0);
    CHECK(frig_ctx_get_param(ctx, FRIG_PARAM_DETECT_SCALE_FACTOR) == 1.1);
    CHECK(frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_SCALE_FACTOR, 1.2) == FRIG_OK);
    CHECK(frig_ctx_get_param(ctx, FRIG_PARAM_DETECT_SCALE_FACTOR) == 1.2);
    CHECK(frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_SCALE_FACTOR, 0.5) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(strstr(frig_ctx_errmsg(ctx), "detect.scale_factor") != NULL);
    CHECK(frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_MIN_NEIGHBORS, 2.5) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_ctx_set_param(ctx, (frig_param)99999, 1) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(isnan(frig_ctx_get_param(ctx, (frig_param)99999)));
    frig_param p;
    CHECK(frig_param_lookup(ctx, "filter.omega", &p) == FRIG_OK && p == FRIG_PARAM_FILTER_OMEGA);
    CHECK(frig_param_lookup(ctx, "filter.nonsense", &p) == FRIG_ERR_INVALID_ARGUMENT);
    /* Every parameter's default lies within its bounds and round-trips by name. */
    for (size_t i = 0; i < frig_param_count(); i++) {
        frig_param q = frig_param_at(i);
        CHECK(frig_ctx_set_param(ctx, q, frig_param_default(q)) == FRIG_OK);
        frig_param r;
        CHECK(frig_param_lookup(ctx, frig_param_name(q), &r) == FRIG_OK && r == q);
        CHECK(frig_param_help(q) && frig_param_help(q)[0]);
    }
    frig_ctx_clear_error(ctx);
    CHECK(frig_ctx_status(ctx) == FRIG_OK);

    CHECK(frig_ctx_set_threads(ctx, -1) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_ctx_set_threads(ctx, 2) == FRIG_OK && frig_ctx_threads(ctx) == 2);
    CHECK(fr_threads(ctx) == 2);

    CHECK(fr_check_cancel(ctx, "x") == FRIG_OK);
    frig_ctx_cancel(ctx);
    CHECK(fr_check_cancel(ctx, "the test loop") == FRIG_ERR_CANCELLED);
    CHECK(strstr(frig_ctx_errmsg(ctx), "the test loop") != NULL);
    frig_ctx_reset_cancel(ctx);
    CHECK(!fr_cancelled(ctx));

    frig_ctx_set_progress(ctx, on_progress, NULL);
    atomic_size_t counter;
    atomic_init(&counter, 0);
#pragma omp parallel for num_threads(2)
    for (int i = 0; i < 100; i++) fr_progress_tick(ctx, &counter, "test", 100);
    CHECK(progress_calls == 100 && last_done == 100);
    frig_ctx_free(ctx);
    return test_result("test_context");
}
