/* The benchmark programs' --set NAME=VALUE option (any parameter, as `frig --set`). */
#ifndef BENCH_PARAM_H
#define BENCH_PARAM_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frig/core.h"

/* Set the parameter that arg ("NAME=VALUE") names; 0 on success, else prints why. */
static int bench_set_param(frig_ctx *ctx, const char *arg) {
    char name[128];
    const char *eq = strchr(arg, '=');
    frig_param p;
    if (!eq || (size_t)(eq - arg) >= sizeof name) {
        fprintf(stderr, "--set wants NAME=VALUE, not %s\n", arg);
        return -1;
    }
    memcpy(name, arg, (size_t)(eq - arg));
    name[eq - arg] = 0;
    if (frig_param_lookup(ctx, name, &p) || frig_ctx_set_param(ctx, p, atof(eq + 1))) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return -1;
    }
    return 0;
}

#endif
