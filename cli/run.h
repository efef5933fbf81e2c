/* frig run: the whole pipeline in one command (docs/run.md). The stages are the rows of one
 * table (run_stages.c): a name, the parameters and options that change its result, what it
 * reads and writes, and how to run it. The runner (cmd_run.c) keeps a record per stage in
 * OUT/stages/NAME/stage.json (the options it ran with, a digest of what it wrote, its time
 * and memory) and reruns a stage only when its options, its input or its outputs changed,
 * so an interrupted or changed run picks up where it stands. Uses only the public headers. */
#ifndef FRIG_CLI_RUN_H
#define FRIG_CLI_RUN_H

#include <stdint.h>

#include <cJSON.h>

#include "cli.h"

/* A stage's run function may also return this: too few usable photos; the run stops after
 * writing the report, with r->stop saying why. */
enum { RUN_STOP = 3, RUN_INTERRUPTED = 130 };

typedef struct run_ctx run_ctx;

typedef struct run_stage {
    const char *name;    /* "detect": its record OUT/stages/NAME/, its label on the progress bar */
    const char *what;    /* one line for logs and the report */
    const char *params;  /* prefixes of the parameters that change its result ("detect. image.") */
    const char *inputs;  /* what it reads, for docs and the report */
    const char *outputs; /* files and folders under OUT it writes, space-separated; a leading
                          * '@' stands for the rig's paths (@glb, @shapes) */
    const char *digest;  /* the outputs later stages read (hashed into their keys) */
    int report;          /* 1: it changes report.json (snapshot OUT/stages/NAME/report.json) */
    int rig;             /* 1: it makes the rig (snapshot OUT/stages/NAME/rig.frigrig, also the
                          * workspace's current rig OUT/rig/rig.frigrig); later stages read the
                          * last such snapshot, never the current file another stage may replace */
    /* 1 when the stage has work in this run (NULL: always) */
    int (*wanted)(run_ctx *r);
    /* its options besides parameters (input files and their hashes, ...) into opts; NULL: none */
    int (*options)(run_ctx *r, cJSON *opts);
    /* do it: CLI_OK, CLI_FAILED, RUN_STOP or RUN_INTERRUPTED */
    int (*run)(run_ctx *r);
} run_stage;

extern const run_stage run_stages[];
extern const int run_stage_count;

/* One photo source in command-line order: a photo, or a video and the frames taken from it. */
typedef struct run_source {
    const char *path; /* absolute */
    int video;
    char frames[4096]; /* video: OUT/frames/NAME, its frames NAME_NNNN.jpg */
    char name[256];
} run_source;

/* What one stage did in this invocation, or its record from an earlier one. */
typedef struct run_result {
    int done;          /* up to date now (ran or was up to date) */
    int ran;           /* ran in this invocation */
    int stopped;       /* it stopped the run (r->stop says why; kept in its record) */
    double seconds;    /* when it last ran: wall time */
    double cpu_seconds; /* user + system CPU time of the process (all threads) during it */
    double peak_rss_mb;
    char key[17], digest[17];
    char summary[512];
} run_result;

struct run_ctx {
    cli_env *env;
    char out[4096];       /* the run's folder (the workspace) */
    cli_rig_paths rig;    /* where rig.glb and the OBJ folder go */
    const char *model_given, *cascades, *landmark_model, *face_models;
    int no_report;
    run_source *sources;
    size_t source_count;
    frig_model *model;    /* loaded when a stage needs it */
    /* the stage running now */
    int stage;
    char build[17];       /* run_build_hash: which build made the stages' outputs */
    char from[4096];      /* the folder whose report.json the stage starts from */
    char rig_from[4200];  /* the rig the stage starts from (the last rig stage's snapshot) */
    char stop[1024];      /* why the run stopped (RUN_STOP) */
    run_result results[16];
    double t0;            /* start of the invocation (monotonic seconds) */
    /* progress */
    int tty;
    double stage_t0, sub_t0;
    char sub[64];
    size_t offset, total; /* detect in batches: items done before this call, items in all */
    double line_t;        /* the last plain progress line */
    volatile int interrupted;
    volatile long child_pid; /* ffmpeg while it runs */
};

/* ---- run_files.c: hashes, file lists, atomic writes ---- */
typedef struct run_hash {
    uint64_t h;
} run_hash;
void run_hash_init(run_hash *h);
void run_hash_bytes(run_hash *h, const void *data, size_t n);
void run_hash_str(run_hash *h, const char *s);
/* The file's contents; -1 (and errno) when it cannot be read. */
int run_hash_file(run_hash *h, const char *path);
void run_hex(uint64_t v, char out[17]);
/* ---- run_build.c ---- */
/* A hash of the version, the frig program's bytes and the loaded libfrig's (-1 when one cannot be read:
 * the hash is then of what could be). */
int run_build_hash(char out[17]);
/* Regular, non-hidden files of a folder in name order (malloc'd paths; caller frees each and
 * the array). -1 when the folder cannot be read (a missing folder: 0 files, returns 0). */
int run_list_files(const char *dir, char ***out, size_t *count);
/* Write a whole file through a temporary beside it, renamed into place. -1 with errno. */
int run_write_atomic(const char *path, const void *data, size_t size);
/* Read a whole file (NUL-terminated); NULL when it cannot be read. */
char *run_read_text(const char *path, size_t *size);
/* Remove the temporary files an interrupted writer left (".NAME.XXXXXX") in dir. */
void run_remove_temps(const char *dir);
/* rm -r of a folder the run owns. */
int run_remove_tree(const char *path);
double run_now(void);
double run_cpu_now(void); /* user + system CPU seconds of the process so far */
/* Peak resident memory: reset it (Linux: /proc/self/clear_refs) and read it, in MB. */
void run_peak_reset(void);
double run_peak_mb(void);

/* ---- run_progress.c: the bar on a terminal, log lines otherwise ---- */
void run_progress_install(run_ctx *r);
void run_progress_stage(run_ctx *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A stage's sub-range of items (detect in batches): progress shows offset + done of total. */
void run_progress_range(run_ctx *r, size_t offset, size_t total);
void run_progress_done(run_ctx *r); /* clear the bar */

/* ---- run_video.c: frames from videos with ffmpeg ---- */
/* 1 when ffmpeg and ffprobe are on PATH. */
int run_have_ffmpeg(void);
/* Sample 'frames' frames evenly spread over the video into src->frames/NAME_NNNN.jpg (made
 * anew), with 'meta' as src->frames/frames.json (what they were taken from). */
int run_video_frames(run_ctx *r, const run_source *src, int frames, const char *meta);

/* ---- report_html.c: OUT/report.html ---- */
int run_write_report(run_ctx *r);

/* ---- cmd_run.c helpers the stages use ---- */
/* OUT/rel in buf. */
const char *run_path(const run_ctx *r, const char *rel, char *buf, size_t size);
int run_load_model(run_ctx *r);
/* Load the report the stage starts from (r->from), and save the stage's result: OUT/report.json
 * and the stage's snapshot. */
int run_load_set(run_ctx *r, frig_photoset **set);
int run_save_set(run_ctx *r, const frig_photoset *set);
/* Save the stage's rig: its snapshot and the workspace's current rig. */
int run_save_rig(run_ctx *r, const frig_rig *rig);
/* Count photos by status; usable = ok (and fitted when fitted is 1). Then the sentence for
 * too few, into r->stop, and RUN_STOP; else CLI_OK. */
int run_check_enough(run_ctx *r, const frig_photoset *set, int fitted);
/* Fewer photos used than this and the report says the shape is held back by it (docs/run.md, "How
 * many photos": rigs from 4-8 used photos were half again as far from the truth as from 20-30). */
#define RUN_FEW_PHOTOS 9
/* The running stage's one-line result (cut to fit). */
void run_summary(run_ctx *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* "6 no_face, 2 outlier" for the photos that are not usable. */
void run_dropped_sentence(const frig_photoset *set, char *buf, size_t size);

#endif
