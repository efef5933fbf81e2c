/* frig synth: synthetic subjects (true rigs outside the model's span) and photos of them
 * with their ground truth, for measuring every stage (paper section 7.2). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <frig/synth.h>

#include "cli.h"

const char cmd_synth_usage[] =
    "usage: frig synth [--model FILE] -o DIR [--subjects S] [--photos N] [--seed K]\n"
    "\n"
    "Make S synthetic subjects (default 1) with N photos each (default 20) from seed K\n"
    "(default 1) and write:\n"
    "  DIR/index.json                         every subject and photo, failure kinds\n"
    "  DIR/subject_SS/subject.json            identity weights, offset RMS, expression changes\n"
    "  DIR/subject_SS/rig/                    the true rig: rig.frigrig, rig.glb, shapes/*.obj\n"
    "  DIR/subject_SS/photos/photo_PPP.jpg    the photos\n"
    "  DIR/subject_SS/truth/photo_PPP.json    pose, camera, expression, lighting, landmarks\n"
    "  DIR/subject_SS/truth/photo_PPP.depth.f32  depth map (float32 little-endian, metres)\n"
    "The same seed gives the same bytes whatever --threads is. Parameters: synth.image_size,\n"
    "synth.max_yaw, synth.offset_mm, synth.failure_rate (frig help params). Formats:\n"
    "docs/synth.md.\n"
    "\n"
    "The model is --model FILE, else $FRIG_MODEL, else $XDG_DATA_HOME/frig/ict.frigmodel,\n"
    "else ~/.local/share/frig/ict.frigmodel.\n";

static int parse_count(const char *text, const char *what, long lo, long hi, long *out) {
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < lo || v > hi)
        return cli_usage_error("synth", "%s wants a whole number in %ld..%ld, not '%s'", what, lo, hi, text);
    *out = v;
    return CLI_OK;
}

int cmd_synth(cli_env *env, int argc, char **argv) {
    const char *given = NULL, *out = NULL;
    long subjects = 1, photos = 20;
    unsigned long long seed = 1;
    int rc = CLI_OK;
    for (int i = 0; i < argc && rc == CLI_OK; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) rc = cli_usage_error("synth", "'%s' wants a value (see frig help synth)", a);
        else if (strcmp(a, "--model") == 0) given = v, i++;
        else if (strcmp(a, "-o") == 0) out = v, i++;
        else if (strcmp(a, "--subjects") == 0) rc = parse_count(v, "--subjects", 1, 10000, &subjects), i++;
        else if (strcmp(a, "--photos") == 0) rc = parse_count(v, "--photos", 0, 100000, &photos), i++;
        else if (strcmp(a, "--seed") == 0) {
            char *end;
            errno = 0;
            seed = strtoull(v, &end, 0);
            if (errno || end == v || *end || v[0] == '-')
                rc = cli_usage_error("synth", "--seed wants a whole number >= 0, not '%s'", v);
            i++;
        } else rc = cli_usage_error("synth", "unknown argument '%s'", a);
    }
    if (rc) return rc;
    if (!out) return cli_usage_error("synth", "no output folder given (-o DIR)");
    frig_model *m = NULL;
    if ((rc = cli_load_model(env, "synth", given, &m))) return rc;
    frig_status s = frig_synth_dataset(env->ctx, m, out, (int)subjects, (int)photos, (uint64_t)seed);
    frig_model_free(m);
    if (s) return cli_fail(env, "synth");
    frig_param rate;
    frig_param_lookup(env->ctx, "synth.failure_rate", &rate);
    printf("%s: %ld subject%s x %ld photos (%ld intended failures each), seed %llu\n", out, subjects,
           subjects == 1 ? "" : "s", photos, (long)(frig_ctx_get_param(env->ctx, rate) * (double)photos + 0.5), seed);
    return CLI_OK;
}
