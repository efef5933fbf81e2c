/* The sfs block of a photo in report.json (sfs_report.c). Internal. */
#ifndef FR_WORKSPACE_SFS_REPORT_H
#define FR_WORKSPACE_SFS_REPORT_H

#include <cJSON.h>

#include "io/json_writer.h"
#include "workspace/photoset.h"

void fr_report_write_sfs(fr_json *j, const frig_photoset *set, const fr_photo *p);
/* 1 when the block is well formed (then p has it), else 0. */
/* 1 when a is an array of exactly n numbers, copied to out (report.c). */
int fr_report_read_numbers(const cJSON *a, double *out, int n);
int fr_report_read_sfs(frig_ctx *ctx, const cJSON *sfs, frig_photoset *set, size_t i);
/* The set's "sfs" block (the shared solve), written when the stage has run; read back (absent in
 * older reports: none recorded). */
void fr_report_write_set_sfs(fr_json *j, const frig_photoset *set);
frig_status fr_report_read_set_sfs(frig_ctx *ctx, frig_photoset *set, const cJSON *root);

#endif
