/* Human-friendly JSON output with exact number round trips. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_writer.h"

void fr_json_format_number(char buf[32], double v) {
    if (!isfinite(v)) {
        strcpy(buf, "null");
        return;
    }
    if (v == 0) {
        strcpy(buf, "0");
        return;
    }
    char tmp[32];
    for (int prec = 6; prec <= 17; prec++) {
        snprintf(tmp, sizeof tmp, "%.*g", prec, v);
        if (strtod(tmp, NULL) == v) break;
    }
    memcpy(buf, tmp, sizeof tmp);
    /* A locale with a decimal comma must not leak into JSON. */
    for (char *c = buf; *c; c++)
        if (*c == ',') *c = '.';
}

static void newline(fr_json *j) {
    fputc('\n', j->fp);
    for (int i = 0; i < j->depth; i++) fputs("  ", j->fp);
}

static void prefix(fr_json *j, const char *key) {
    if (j->depth > 0) {
        if (!j->first[j->depth]) fputc(',', j->fp);
        if (j->inline_[j->depth]) {
            if (!j->first[j->depth]) fputc(' ', j->fp);
        } else {
            newline(j);
        }
        j->first[j->depth] = 0;
    }
    if (key) {
        fputc('"', j->fp);
        fputs(key, j->fp);
        fputs("\": ", j->fp);
    }
}

static void open_container(fr_json *j, const char *key, char c, int on_one_line) {
    int parent_inline = j->depth > 0 && j->inline_[j->depth];
    prefix(j, key);
    fputc(c, j->fp);
    if (j->depth < 31) j->depth++;
    j->first[j->depth] = 1;
    j->inline_[j->depth] = on_one_line || parent_inline;
    j->close[j->depth] = c == '{' ? '}' : ']';
}

void fr_json_begin(fr_json *j, FILE *fp) {
    memset(j, 0, sizeof *j);
    j->fp = fp;
}

void fr_json_object(fr_json *j, const char *key) { open_container(j, key, '{', 0); }
void fr_json_array(fr_json *j, const char *key, int on_one_line) { open_container(j, key, '[', on_one_line); }

void fr_json_end(fr_json *j) {
    int was_inline = j->inline_[j->depth], was_empty = j->first[j->depth];
    char close = j->close[j->depth];
    j->depth--;
    if (!was_inline && !was_empty) newline(j);
    fputc(close, j->fp);
}

void fr_json_number(fr_json *j, const char *key, double v) {
    char buf[32];
    fr_json_format_number(buf, v);
    prefix(j, key);
    fputs(buf, j->fp);
}

void fr_json_int(fr_json *j, const char *key, long long v) {
    prefix(j, key);
    fprintf(j->fp, "%lld", v);
}

void fr_json_bool(fr_json *j, const char *key, int v) {
    prefix(j, key);
    fputs(v ? "true" : "false", j->fp);
}

void fr_json_null(fr_json *j, const char *key) {
    prefix(j, key);
    fputs("null", j->fp);
}

void fr_json_string(fr_json *j, const char *key, const char *s) {
    prefix(j, key);
    fputc('"', j->fp);
    for (const unsigned char *c = (const unsigned char *)(s ? s : ""); *c; c++) {
        switch (*c) {
        case '"': fputs("\\\"", j->fp); break;
        case '\\': fputs("\\\\", j->fp); break;
        case '\n': fputs("\\n", j->fp); break;
        case '\r': fputs("\\r", j->fp); break;
        case '\t': fputs("\\t", j->fp); break;
        default:
            if (*c < 0x20) fprintf(j->fp, "\\u%04x", *c);
            else fputc(*c, j->fp);
        }
    }
    fputc('"', j->fp);
}

void fr_json_finish(fr_json *j) { fputc('\n', j->fp); }
