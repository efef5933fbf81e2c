/* A small JSON writer that lays files out for people: nested objects indented, short
 * arrays of numbers on one line. Numbers are written in the shortest form that reads back
 * to the same double, so a workspace round-trips exactly. Internal. */
#ifndef FR_IO_JSON_WRITER_H
#define FR_IO_JSON_WRITER_H

#include <stdio.h>

typedef struct fr_json {
    FILE *fp;
    int depth;
    int first[32];  /* nothing written yet at this depth */
    int inline_[32]; /* this container is written on one line */
    char close[32];  /* the character that closes it */
} fr_json;

void fr_json_begin(fr_json *j, FILE *fp);
void fr_json_object(fr_json *j, const char *key);           /* key NULL inside arrays / at top */
void fr_json_array(fr_json *j, const char *key, int on_one_line);
void fr_json_end(fr_json *j);                               /* closes the innermost container */
void fr_json_number(fr_json *j, const char *key, double v);
void fr_json_int(fr_json *j, const char *key, long long v);
void fr_json_string(fr_json *j, const char *key, const char *s);
void fr_json_bool(fr_json *j, const char *key, int v);
void fr_json_null(fr_json *j, const char *key);
void fr_json_finish(fr_json *j); /* final newline */

/* Shortest text that strtod reads back exactly (non-finite values become null). */
void fr_json_format_number(char buf[32], double v);

#endif
