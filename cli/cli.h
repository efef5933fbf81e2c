/* The frig command: shared pieces of the subcommands. Uses only the public headers. */
#ifndef FRIG_CLI_H
#define FRIG_CLI_H

#include <frig/frig.h>

typedef struct cli_env {
    frig_ctx *ctx;
    int quiet;
    int verbose;
    int progress_shown;
} cli_env;

typedef struct cli_command {
    const char *name;
    int (*run)(cli_env *env, int argc, char **argv);
    const char *summary;
    const char *usage; /* full help text */
} cli_command;

/* Exit codes. */
enum { CLI_OK = 0, CLI_FAILED = 1, CLI_USAGE = 2 };

/* Print "frig CMD: message" to stderr; returns CLI_USAGE or CLI_FAILED for chaining. */
int cli_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
int cli_fail(cli_env *env, const char *cmd);  /* the context's error sentence */
void cli_note(cli_env *env, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* mkdir -p; prints the error and returns CLI_FAILED on failure. */
int cli_make_dir(cli_env *env, const char *path);


/* Print "frig CMD: message" to stderr and return CLI_FAILED (exit 1): a run that cannot go on. */
int cli_fail_msg(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Where -o puts a rig: a folder OUT gets OUT/rig.glb and OUT/shapes/; a name OUT.glb gets
 * OUT.glb and OUT_shapes/ beside it. Any other extension is a usage error. */
typedef struct cli_rig_paths {
    char glb[4096], shapes[4096], folder[4096]; /* folder: where both go */
} cli_rig_paths;
int cli_rig_paths_of(const char *cmd, const char *out, cli_rig_paths *p);
/* The rig's glTF and OBJ files where -o OUT says (above), with the face texture when given
 * (a PNG path, may be NULL), and a summary of the targets on stdout. */
int cli_export_rig(cli_env *env, const char *cmd, frig_rig *rig, const char *out, const char *texture);
/* Remove the *.jpg files in a folder (an earlier run's overlays). */
void cli_clear_jpegs(const char *dir);
/* The sfs stage's shared solve in words, for its summary line ("the full shared solve", "the light
 * shared solve: the lights fall along one axis, 0.979"); "" when the stage has not run. */
const char *cli_sfs_solve_words(const frig_photoset *set, char *buf, size_t size);

/* Inputs named on the command line (inputs.c): photos, and videos for frig run. */
typedef struct cli_input {
    char *path; /* absolute when it resolves */
    int video;
} cli_input;
typedef struct cli_inputs {
    cli_input *items;
    size_t count, cap;
} cli_inputs;
/* A photo, a video (allow_videos), or a folder's photos in name order (or, when it holds
 * none and allow_videos, its videos). A missing path: the sentence and CLI_FAILED. */
int cli_inputs_add(const char *cmd, cli_inputs *in, const char *arg, int allow_videos);
void cli_inputs_free(cli_inputs *in);
int cli_is_photo_name(const char *name);
int cli_is_video_name(const char *name);
/* --model FILE (given, may be NULL) or the default model path into buf; load it. */
int cli_model_path(cli_env *env, const char *cmd, const char *given, char *buf, size_t size);
int cli_load_model(cli_env *env, const char *cmd, const char *given, frig_model **m);

/* Subcommands. */
int cmd_info(cli_env *env, int argc, char **argv);
extern const char cmd_info_usage[];
int cmd_detect(cli_env *env, int argc, char **argv);
extern const char cmd_detect_usage[];
int cmd_identify(cli_env *env, int argc, char **argv);
extern const char cmd_identify_usage[];
/* The identity step on a loaded set, with the summary line; CLI_FAILED (sentence printed)
 * when the set has no dominant identity. */
int cli_identify(cli_env *env, const char *cmd, frig_photoset *set);
int cmd_model(cli_env *env, int argc, char **argv);
extern const char cmd_model_usage[];
int cmd_filter(cli_env *env, int argc, char **argv);
extern const char cmd_filter_usage[];
int cmd_fit(cli_env *env, int argc, char **argv);
extern const char cmd_fit_usage[];
int cmd_sfs(cli_env *env, int argc, char **argv);
extern const char cmd_sfs_usage[];
int cmd_retarget(cli_env *env, int argc, char **argv);
extern const char cmd_retarget_usage[];
int cmd_export(cli_env *env, int argc, char **argv);
extern const char cmd_export_usage[];
int cmd_synth(cli_env *env, int argc, char **argv);
extern const char cmd_synth_usage[];
int cmd_run(cli_env *env, int argc, char **argv);
extern const char cmd_run_usage[];

#endif
