/* Pieces several subcommands share: folders, where a rig goes and writing it for users, the
 * sfs stage inside retarget's outer loop. */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

int cli_make_dir(cli_env *env, const char *path) {
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *c = buf + 1;; c++) {
        if (*c == '/' || *c == 0) {
            char keep = *c;
            *c = 0;
            if (mkdir(buf, 0755) != 0 && errno != EEXIST) {
                if (env->progress_shown) fputc('\n', stderr), env->progress_shown = 0;
                fprintf(stderr, "frig: cannot create folder %s: %s\n", buf, strerror(errno));
                return CLI_FAILED;
            }
            *c = keep;
            if (!keep) break;
        }
    }
    return CLI_OK;
}

void cli_clear_jpegs(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        const char *dot = strrchr(e->d_name, '.');
        if (e->d_name[0] == '.' || !dot || strcmp(dot, ".jpg") != 0) continue;
        char path[PATH_MAX];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) < (int)sizeof path) unlink(path);
    }
    closedir(d);
}

int cli_rig_paths_of(const char *cmd, const char *out, cli_rig_paths *p) {
    size_t n = strlen(out);
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    struct stat st;
    int named = dot && (!slash || dot > slash) && dot != out && dot[-1] != '/' &&
                !(stat(out, &st) == 0 && S_ISDIR(st.st_mode)); /* an existing folder "a.b" stays a folder */
    if (named && strcasecmp(dot, ".glb") != 0)
        return cli_usage_error(cmd, "-o %s: frig writes binary glTF; give a NAME.glb or a folder", out);
    if (named) {
        if (n + 1 > sizeof p->glb || (size_t)(dot - out) + 8 > sizeof p->shapes)
            return cli_usage_error(cmd, "output path too long");
        snprintf(p->glb, sizeof p->glb, "%s", out);
        snprintf(p->shapes, sizeof p->shapes, "%.*s_shapes", (int)(dot - out), out);
        snprintf(p->folder, sizeof p->folder, "%.*s", slash ? (int)(slash - out) : 1, slash ? out : ".");
        if (slash == out) snprintf(p->folder, sizeof p->folder, "/");
    } else {
        if (n + 16 > sizeof p->glb) return cli_usage_error(cmd, "output path too long");
        snprintf(p->glb, sizeof p->glb, "%s/rig.glb", out);
        snprintf(p->shapes, sizeof p->shapes, "%s/shapes", out);
        snprintf(p->folder, sizeof p->folder, "%s", out);
    }
    return CLI_OK;
}

int cli_export_rig(cli_env *env, const char *cmd, frig_rig *rig, const char *out, const char *texture) {
    cli_rig_paths p;
    int rc = cli_rig_paths_of(cmd, out, &p);
    if (rc) return rc;
    if (texture && frig_rig_set_face_texture(env->ctx, rig, texture)) return cli_fail(env, cmd);
    if (cli_make_dir(env, p.folder)) return CLI_FAILED;
    if (frig_rig_save_obj(env->ctx, rig, p.shapes)) return cli_fail(env, cmd);
    if (frig_rig_save_gltf(env->ctx, rig, p.glb)) return cli_fail(env, cmd);
    printf("%s and %s/ (neutral.obj + %d shapes)%s%s\n", p.glb, p.shapes, frig_rig_target_count(rig),
           texture ? "; face texture " : "", texture ? texture : "");
    printf("targets (%d):", frig_rig_target_count(rig));
    for (int i = 0; i < frig_rig_target_count(rig); i++) printf(" %s", frig_rig_target_name(rig, i));
    printf("\nARKit names not provided:");
    int missing = 0;
    for (int i = 0; i < frig_arkit_name_count(); i++)
        if (!frig_rig_provides_arkit(rig, frig_arkit_name(i))) printf(" %s", frig_arkit_name(i)), missing++;
    printf("%s\n", missing ? "" : " none");
    return CLI_OK;
}

const char *cli_sfs_solve_words(const frig_photoset *set, char *buf, size_t size) {
    int photos;
    double axis;
    const char *why;
    frig_sfs_solve solve = frig_photoset_sfs_solve(set, &photos, &axis, &why);
    if (solve == FRIG_SFS_SOLVE_FULL)
        snprintf(buf, size, "the full shared solve (lights' axis %.3f)", axis);
    else if (solve == FRIG_SFS_SOLVE_LIGHT && !strcmp(why, "one_light_axis"))
        snprintf(buf, size, "the light shared solve: the lights fall on the face along one axis (%.3f)", axis);
    else if (solve == FRIG_SFS_SOLVE_LIGHT && !strcmp(why, "outer_loop"))
        snprintf(buf, size, "the light shared solve of the outer loop's last recovery (%d photos judged)", photos);
    else if (solve == FRIG_SFS_SOLVE_LIGHT && !strcmp(why, "few_photos"))
        snprintf(buf, size, "the light shared solve: %d photo%s judged, under sfs.joint_min_photos", photos,
                 photos == 1 ? "" : "s");
    else if (solve == FRIG_SFS_SOLVE_LIGHT)
        snprintf(buf, size, "the light shared solve: %d photos judged, over sfs.joint_max_photos", photos);
    else
        snprintf(buf, size, "%s", "");
    return buf;
}
