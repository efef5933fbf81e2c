/* One parallel loop over independent items (photos, files) for every stage: per-item contexts
 * so one item's failure is recorded apart from the others', progress, cancellation, and the
 * first failure in index order as the loop's result, so the outcome never depends on threads. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/context.h"

frig_status fr_parallel_items(frig_ctx *ctx, size_t n, const char *stage, fr_item_fn fn, void *user) {
    frig_status *fails = calloc(n ? n : 1, sizeof *fails);
    char (*msgs)[FR_ERRMSG_SIZE] = calloc(n ? n : 1, sizeof *msgs);
    if (!fails || !msgs) {
        free(fails);
        free(msgs);
        return fr_nomem(ctx, "per-item results");
    }
    atomic_size_t done;
    atomic_init(&done, 0);
    fr_progress(ctx, stage, 0, n);
#pragma omp parallel for schedule(dynamic, 1) num_threads(fr_threads(ctx))
    for (size_t i = 0; i < n; i++) {
        if (fr_cancelled(ctx)) continue;
        frig_ctx child;
        fr_ctx_init_child(&child, ctx);
        fails[i] = fn(&child, i, user);
        if (fails[i]) snprintf(msgs[i], sizeof msgs[i], "%s", frig_ctx_errmsg(&child));
        fr_progress_tick(ctx, &done, stage, n);
    }
    frig_status st = fr_check_cancel(ctx, stage);
    for (size_t i = 0; i < n && !st; i++)
        if (fails[i]) st = fr_error(ctx, fails[i], "%s", msgs[i]);
    free(fails);
    free(msgs);
    return st;
}
