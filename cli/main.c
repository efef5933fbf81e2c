/* frig: the command line. One subcommand per stage, reading and writing a workspace
 * folder; global options (--threads, --quiet, --verbose, --set NAME=VALUE) go anywhere. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "cli.h"

static const cli_command commands[] = {
    {"run", cmd_run, "the whole pipeline: photos or videos in, rig.glb and report.html out (resumable)",
     cmd_run_usage},
    {"info", cmd_info, "describe images as libfrig reads them", cmd_info_usage},
    {"detect", cmd_detect, "find faces and 68 landmarks in photos, write report.json and overlays",
     cmd_detect_usage},
    {"identify", cmd_identify, "choose the subject's face by face descriptors, mark other people (after detect)",
     cmd_identify_usage},
    {"filter", cmd_filter, "drop photos whose landmarks failed (robust PCA, section 4.2)", cmd_filter_usage},
    {"fit", cmd_fit, "fit the face model to the workspace's photos (sections 4.3-4.4)", cmd_fit_usage},
    {"sfs", cmd_sfs, "point clouds from each photo's shading, the subject's albedo (section 5.1)", cmd_sfs_usage},
    {"retarget", cmd_retarget, "personalize the rig from the photos' point clouds (sections 5.2-5.3)",
     cmd_retarget_usage},
    {"export", cmd_export, "write the workspace's rig as glTF and OBJ files", cmd_export_usage},
    {"model", cmd_model, "import the ICT-FaceKit model, describe it, export its rig", cmd_model_usage},
    {"synth", cmd_synth, "render synthetic subjects and photos with their ground truth", cmd_synth_usage},
};
#define N_COMMANDS (sizeof commands / sizeof commands[0])

static const char global_usage[] =
    "usage: frig [--threads N] [--quiet | --verbose] [--set NAME=VALUE]... COMMAND [ARGS]\n"
    "       frig --version | help [COMMAND | params]\n"
    "\n"
    "Global options:\n"
    "  --threads N        worker threads (0 = one per core; results do not depend on it)\n"
    "  --quiet            no progress bar and no notes, only errors\n"
    "  --verbose          also the stages' working notes (rounds, ranks, thresholds)\n"
    "  --set NAME=VALUE   set a parameter (frig help params lists them)\n";

int cli_usage_error(const char *cmd, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "frig%s%s: ", cmd ? " " : "", cmd ? cmd : "");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return CLI_USAGE;
}

int cli_fail_msg(const char *cmd, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "frig %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return CLI_FAILED;
}

int cli_fail(cli_env *env, const char *cmd) {
    if (env->progress_shown) fputc('\n', stderr), env->progress_shown = 0;
    fprintf(stderr, "frig %s: %s\n", cmd, frig_ctx_errmsg(env->ctx));
    return CLI_FAILED;
}

void cli_note(cli_env *env, const char *fmt, ...) {
    if (env->quiet) return;
    if (env->progress_shown) fputc('\n', stderr), env->progress_shown = 0;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

static void progress_bar(void *user, const char *stage, size_t done, size_t total) {
    cli_env *env = user;
    int width = 30, filled = total ? (int)((double)done / (double)total * width) : width;
    char bar[64];
    for (int i = 0; i < width; i++) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    fprintf(stderr, "\r%-16s [%s] %zu/%zu", stage, bar, done, total);
    if (done >= total) fputc('\n', stderr), env->progress_shown = 0;
    else env->progress_shown = 1;
    fflush(stderr);
}

static void log_line(void *user, frig_log_level level, const char *msg) {
    cli_env *env = user;
    if (env->progress_shown) fputc('\n', stderr), env->progress_shown = 0;
    fprintf(stderr, "%s%s\n", level == FRIG_LOG_ERROR ? "error: " : level == FRIG_LOG_WARNING ? "warning: " : "", msg);
}

static const cli_command *find_command(const char *name) {
    for (size_t i = 0; i < N_COMMANDS; i++)
        if (strcmp(commands[i].name, name) == 0) return &commands[i];
    return NULL;
}

static void list_params(void) {
    printf("Parameters (set with --set NAME=VALUE):\n");
    for (size_t i = 0; i < frig_param_count(); i++) {
        frig_param p = frig_param_at(i);
        printf("  %-26s %-10g %s\n", frig_param_name(p), frig_param_default(p), frig_param_help(p));
    }
}

static int help(int argc, char **argv) {
    if (argc >= 1) {
        if (strcmp(argv[0], "params") == 0) {
            list_params();
            return CLI_OK;
        }
        const cli_command *c = find_command(argv[0]);
        if (!c) return cli_usage_error("help", "unknown command '%s'", argv[0]);
        fputs(c->usage, stdout);
        return CLI_OK;
    }
    fputs(global_usage, stdout);
    printf("\nCommands:\n");
    for (size_t i = 0; i < N_COMMANDS; i++) printf("  %-10s %s\n", commands[i].name, commands[i].summary);
    printf("\nfrig help COMMAND shows a command's options.\n");
    return CLI_OK;
}

static int set_param(frig_ctx *ctx, const char *arg) {
    const char *eq = strchr(arg, '=');
    if (!eq) return cli_usage_error(NULL, "--set wants NAME=VALUE, not '%s'", arg);
    char name[128];
    size_t n = (size_t)(eq - arg);
    if (n >= sizeof name) return cli_usage_error(NULL, "parameter name too long in '%s'", arg);
    memcpy(name, arg, n);
    name[n] = 0;
    char *end;
    double v = strtod(eq + 1, &end);
    if (end == eq + 1 || *end) return cli_usage_error(NULL, "'%s' is not a number (in --set %s)", eq + 1, arg);
    frig_param p;
    if (frig_param_lookup(ctx, name, &p) || frig_ctx_set_param(ctx, p, v))
        return cli_usage_error(NULL, "%s", frig_ctx_errmsg(ctx));
    return CLI_OK;
}

/* The stages allocate and free buffers of a few megabytes per photo many times over (views,
 * rasters, pyramids); glibc's defaults hand many of them back to the system and fault them in
 * again. A fixed mmap threshold at glibc's largest and a high trim threshold keep them in the
 * heap: frig sfs on a 36-photo subject 13.2 -> 12.1 CPU s (docs/sfs.md, "The sixth pass"). A
 * process-wide choice, so the command makes it, not the library. */
static void tune_malloc(void) {
#ifdef __GLIBC__
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
}

int main(int argc, char **argv) {
    tune_malloc();
    cli_env env = {0};
    env.ctx = frig_ctx_create();
    if (!env.ctx) {
        fprintf(stderr, "frig: out of memory\n");
        return CLI_FAILED;
    }
    /* Pull the global options out, wherever they are. */
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    int nrest = 0, rc = CLI_OK, version = 0;
    for (int i = 1; i < argc && rc == CLI_OK; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--version") == 0 || strcmp(a, "-V") == 0) {
            version = 1;
        } else if (strcmp(a, "--quiet") == 0 || strcmp(a, "-q") == 0) {
            env.quiet = 1;
        } else if (strcmp(a, "--verbose") == 0 || strcmp(a, "-v") == 0) {
            env.verbose = 1;
        } else if (strcmp(a, "--threads") == 0 || strcmp(a, "-j") == 0) {
            char *end;
            long t = i + 1 < argc ? strtol(argv[i + 1], &end, 10) : -1;
            if (i + 1 >= argc || *end || t < 0 || frig_ctx_set_threads(env.ctx, (int)t))
                rc = cli_usage_error(NULL, "--threads wants a number >= 0");
            i++;
        } else if (strcmp(a, "--set") == 0) {
            if (i + 1 >= argc) rc = cli_usage_error(NULL, "--set wants NAME=VALUE");
            else rc = set_param(env.ctx, argv[++i]);
        } else if (strncmp(a, "--set=", 6) == 0) {
            rc = set_param(env.ctx, a + 6);
        } else {
            rest[nrest++] = argv[i];
        }
    }
    if (rc == CLI_OK) {
        if (version) {
            printf("frig %s (libfrig %s)\n", FRIG_VERSION_STRING, frig_version_string());
        } else if (nrest == 0) {
            fputs(global_usage, stderr);
            rc = CLI_USAGE;
        } else if (strcmp(rest[0], "help") == 0 || strcmp(rest[0], "--help") == 0 || strcmp(rest[0], "-h") == 0) {
            rc = help(nrest - 1, rest + 1);
        } else {
            const cli_command *c = find_command(rest[0]);
            if (!c) {
                rc = cli_usage_error(NULL, "unknown command '%s' (frig help lists them)", rest[0]);
            } else if (nrest > 1 && (strcmp(rest[1], "--help") == 0 || strcmp(rest[1], "-h") == 0)) {
                fputs(c->usage, stdout);
            } else {
                if (!env.quiet && isatty(2)) frig_ctx_set_progress(env.ctx, progress_bar, &env);
                frig_ctx_set_log(env.ctx, log_line, &env,
                                 env.quiet ? FRIG_LOG_ERROR : env.verbose ? FRIG_LOG_DEBUG : FRIG_LOG_WARNING);
                rc = c->run(&env, nrest - 1, rest + 1);
            }
        }
    }
    free(rest);
    frig_ctx_free(env.ctx);
    return rc;
}
