/* Frames from video files for frig run: N frames spread evenly over the video (frame n is
 * kept when (n N) mod T < N, T the video's frame count: exactly N of T, evenly spaced), taken
 * by ffmpeg (Debian's ffmpeg package) as JPEGs into a hidden folder that is renamed into
 * place when complete, so an interrupted extraction is never mistaken for a finished one. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "run.h"

static int on_path(const char *name) {
    const char *path = getenv("PATH");
    if (!path) path = "/usr/bin:/bin";
    char buf[4096];
    for (const char *p = path; *p;) {
        const char *colon = strchr(p, ':');
        size_t n = colon ? (size_t)(colon - p) : strlen(p);
        if (n && n + strlen(name) + 2 < sizeof buf) {
            snprintf(buf, sizeof buf, "%.*s/%s", (int)n, p, name);
            if (access(buf, X_OK) == 0) return 1;
        }
        p += n + (colon ? 1 : 0);
    }
    return 0;
}

int run_have_ffmpeg(void) { return on_path("ffmpeg") && on_path("ffprobe"); }

/* Run argv; its stdout into out (may be NULL), its stderr's last line into err. Returns the
 * exit status (-1: could not run, 128+sig: killed). */
static int run_child(run_ctx *r, char *const argv[], char *out, size_t out_size, char *err, size_t err_size) {
    int po[2], pe[2];
    if (pipe(po) || pipe(pe)) return -1;
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        dup2(po[1], 1);
        dup2(pe[1], 2);
        close(po[0]), close(po[1]), close(pe[0]), close(pe[1]);
        execvp(argv[0], argv);
        _exit(127);
    }
    r->child_pid = pid;
    close(po[1]), close(pe[1]);
    size_t no = 0, ne = 0;
    char ebuf[8192];
    int open_o = 1, open_e = 1;
    while (open_o || open_e) {
        fd_set fds;
        FD_ZERO(&fds);
        if (open_o) FD_SET(po[0], &fds);
        if (open_e) FD_SET(pe[0], &fds);
        if (select((po[0] > pe[0] ? po[0] : pe[0]) + 1, &fds, NULL, NULL, NULL) < 0) {
            if (errno == EINTR) continue;
            break;
        }
        char buf[4096];
        if (open_o && FD_ISSET(po[0], &fds)) {
            ssize_t got = read(po[0], buf, sizeof buf);
            if (got <= 0) open_o = 0;
            else if (out)
                for (ssize_t i = 0; i < got && no + 1 < out_size; i++) out[no++] = buf[i];
        }
        if (open_e && FD_ISSET(pe[0], &fds)) {
            ssize_t got = read(pe[0], buf, sizeof buf);
            if (got <= 0) open_e = 0;
            for (ssize_t i = 0; i < got; i++) {
                if (ne + 1 >= sizeof ebuf) memmove(ebuf, ebuf + sizeof ebuf / 2, ne -= sizeof ebuf / 2);
                ebuf[ne++] = buf[i];
            }
        }
    }
    close(po[0]), close(pe[0]);
    if (out) out[no] = 0;
    ebuf[ne] = 0;
    while (ne && (ebuf[ne - 1] == '\n' || ebuf[ne - 1] == '\r')) ebuf[--ne] = 0;
    const char *last = strrchr(ebuf, '\n');
    last = last ? last + 1 : ebuf;
    size_t len = strlen(last) < err_size - 1 ? strlen(last) : err_size - 1;
    memcpy(err, last, len);
    err[len] = 0;
    int status;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    r->child_pid = 0;
    return WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

/* Frames in the video's first video stream (packets counted, no decoding). */
static long frame_count(run_ctx *r, const char *video, char *err, size_t err_size) {
    char *argv[] = {"ffprobe", "-v", "error", "-select_streams", "v:0", "-count_packets", "-show_entries",
                    "stream=nb_read_packets", "-of", "csv=p=0", (char *)video, NULL};
    char out[256];
    int rc = run_child(r, argv, out, sizeof out, err, err_size);
    if (rc) return -1;
    char *end;
    long n = strtol(out, &end, 10);
    if (end == out || n <= 0) {
        snprintf(err, err_size, "ffprobe found no video frames");
        return -1;
    }
    return n;
}

int run_video_frames(run_ctx *r, const run_source *src, int frames, const char *meta) {
    char err[1024] = "";
    long total = frame_count(r, src->path, err, sizeof err);
    if (r->interrupted) return RUN_INTERRUPTED;
    if (total < 0) return cli_fail_msg("run", "%s: cannot read the video (%s)", src->path, err);
    char tmp[4200];
    const char *slash = strrchr(src->frames, '/');
    snprintf(tmp, sizeof tmp, "%.*s/.%s.partial", (int)(slash - src->frames), src->frames, slash + 1);
    run_remove_tree(tmp);
    if (mkdir(tmp, 0755) != 0) return cli_fail_msg("run", "cannot create %s: %s", tmp, strerror(errno));
    long n = frames < total ? frames : total;
    char select[256], pattern[4400];
    snprintf(select, sizeof select, "select='lt(mod(n*%ld,%ld),%ld)'", n, total, n);
    if ((size_t)snprintf(pattern, sizeof pattern, "%s/%s_%%04d.jpg", tmp, src->name) >= sizeof pattern)
        return cli_fail_msg("run", "%s: path too long", src->path);
    char *argv[] = {"ffmpeg", "-nostdin", "-v", "error", "-i", (char *)src->path, "-map", "0:v:0", "-vf", select,
                    "-fps_mode", "passthrough", "-q:v", "2", "-fflags", "+bitexact", "-flags:v", "+bitexact",
                    "-start_number", "1", pattern, NULL};
    int rc = run_child(r, argv, NULL, 0, err, sizeof err);
    if (r->interrupted) return RUN_INTERRUPTED;
    char **names;
    size_t got = 0;
    if (!rc && run_list_files(tmp, &names, &got) == 0) {
        for (size_t i = 0; i < got; i++) free(names[i]);
        free(names);
    }
    if (rc || (long)got != n) {
        run_remove_tree(tmp);
        return cli_fail_msg("run", "%s: ffmpeg %s (%ld of %ld frames)", src->path,
                            rc ? (err[0] ? err : "failed") : "gave another number of frames", (long)got, n);
    }
    char meta_path[4300];
    snprintf(meta_path, sizeof meta_path, "%s/frames.json", tmp);
    if (run_write_atomic(meta_path, meta, strlen(meta))) {
        run_remove_tree(tmp);
        return cli_fail_msg("run", "cannot write %s: %s", meta_path, strerror(errno));
    }
    run_remove_tree(src->frames);
    if (rename(tmp, src->frames) != 0) return cli_fail_msg("run", "cannot rename %s: %s", tmp, strerror(errno));
    return CLI_OK;
}
