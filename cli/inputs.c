/* What the user named on the command line: photos, folders of photos, and (for frig run)
 * video files, in the order given; a folder stands for its photos in name order (or, when it
 * holds none, its videos). A path that does not exist is an error, not an unreadable photo. */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "cli.h"

static int has_ext(const char *name, const char *const *exts) {
    const char *dot = strrchr(name, '.');
    for (; dot && *exts; exts++)
        if (strcasecmp(dot, *exts) == 0) return 1;
    return 0;
}

int cli_is_photo_name(const char *name) {
    static const char *const exts[] = {".jpg", ".jpeg", ".png", NULL};
    return has_ext(name, exts);
}

int cli_is_video_name(const char *name) {
    static const char *const exts[] = {".mp4", ".mov", ".mkv", ".webm", ".m4v", ".avi", NULL};
    return has_ext(name, exts);
}

/* The absolute path of a file, or of its folder and its name when the file itself cannot be
 * resolved (a broken link keeps its own name); the path as given when neither can. */
static char *absolute(const char *path) {
    char abs[PATH_MAX];
    if (realpath(path, abs)) return strdup(abs);
    const char *slash = strrchr(path, '/');
    char *dir = slash ? strndup(path, (size_t)(slash - path + 1)) : strdup(".");
    char *out = NULL;
    if (dir && realpath(dir, abs) && strlen(abs) + strlen(slash ? slash + 1 : path) + 2 <= sizeof abs) {
        size_t len = strlen(abs);
        snprintf(abs + len, sizeof abs - len, "/%s", slash ? slash + 1 : path);
        out = strdup(abs);
    }
    free(dir);
    return out ? out : strdup(path);
}

static int push(cli_inputs *in, const char *path, int video) {
    if (in->count == in->cap) {
        size_t cap = in->cap ? 2 * in->cap : 64;
        cli_input *n = realloc(in->items, cap * sizeof *n);
        if (!n) return -1;
        in->items = n;
        in->cap = cap;
    }
    char *p = absolute(path);
    if (!p) return -1;
    in->items[in->count].path = p;
    in->items[in->count].video = video;
    in->count++;
    return 0;
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* The folder's regular files for which want() holds, sorted by name, and the names for which it
 * holds that cannot be opened (a broken link: the detect stage reports it as unreadable rather
 * than the photo vanishing from the report). */
static int list_folder(const char *dir, int (*want)(const char *), char ***out, size_t *count) {
    DIR *d = opendir(dir);
    if (!d) return -1;
    char **names = NULL;
    size_t n = 0, cap = 0;
    int bad = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL && !bad;) {
        if (e->d_name[0] == '.' || !want(e->d_name)) continue;
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        char *full = malloc(len);
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            char **nn = realloc(names, cap * sizeof *names);
            if (nn) names = nn;
            else cap = n;
        }
        if (!full || n == cap) {
            free(full);
            bad = 1;
            break;
        }
        snprintf(full, len, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(full, &st) != 0 || S_ISREG(st.st_mode)) names[n++] = full;
        else free(full);
    }
    closedir(d);
    if (n) qsort(names, n, sizeof *names, by_name);
    *out = names;
    *count = n;
    return bad ? -2 : 0;
}

int cli_inputs_add(const char *cmd, cli_inputs *in, const char *arg, int allow_videos) {
    struct stat st;
    if (stat(arg, &st) != 0)
        return cli_fail_msg(cmd, "%s: %s", arg, errno == ENOENT ? "no such file or folder" : strerror(errno));
    if (!S_ISDIR(st.st_mode)) {
        if (cli_is_video_name(arg) && !allow_videos)
            return cli_fail_msg(cmd, "%s is a video: frig run samples frames from videos (run.video_frames)", arg);
        return push(in, arg, cli_is_video_name(arg)) ? cli_fail_msg(cmd, "out of memory") : CLI_OK;
    }
    char **names = NULL;
    size_t n = 0;
    int video = 0, r = list_folder(arg, cli_is_photo_name, &names, &n);
    if (r == 0 && n == 0 && allow_videos) {
        free(names);
        names = NULL;
        r = list_folder(arg, cli_is_video_name, &names, &n);
        video = 1;
    }
    int rc = r == -1  ? cli_fail_msg(cmd, "%s: cannot read the folder (%s)", arg, strerror(errno))
             : r      ? cli_fail_msg(cmd, "out of memory listing %s", arg)
             : n == 0 ? cli_fail_msg(cmd, "%s: the folder has no photos (.jpg, .jpeg, .png)%s", arg,
                                     allow_videos ? " or videos (.mp4, .mov, .mkv, .webm, .m4v, .avi)" : "")
                      : CLI_OK;
    for (size_t i = 0; i < n; i++) {
        if (rc == CLI_OK && push(in, names[i], video)) rc = cli_fail_msg(cmd, "out of memory");
        free(names[i]);
    }
    free(names);
    return rc;
}

void cli_inputs_free(cli_inputs *in) {
    for (size_t i = 0; i < in->count; i++) free(in->items[i].path);
    free(in->items);
    memset(in, 0, sizeof *in);
}
