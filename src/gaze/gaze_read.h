/* gaze_read.h: what the gaze readers share (internal to src/gaze/; the public contract is gaze.h).
 *
 * Every reader (gaze_csv.c: fovsim CSV and Pupil Labs; gaze_eyelink.c: EyeLink ASC; gaze_tobii.c:
 * Tobii livedata.json) turns its text into raw samples (time in the file's own unit, x, y
 * normalised, validity, source line) with gaze_push, then gaze_finish sorts them (Tobii only),
 * re-bases the times, averages repeated timestamps and gives every invalid sample the gaze it
 * holds, so that gaze_at is one binary search. gaze_text.c holds these shared parts; gaze.c
 * detects the format and dispatches. The formats are described in docs/gaze-formats.md.
 *
 * The whole file is in memory and parsed in place: no line length limit, NUL bytes are ordinary
 * bytes, and a field is copied only to convert a number (Tobii lines go through cJSON, which
 * builds a tree of each).
 *
 * What it does NOT do: open files (gaze.c), anything a caller outside src/gaze/ may use.
 */
#ifndef FOVSIM_GAZE_READ_H
#define FOVSIM_GAZE_READ_H

#include "gaze/gaze.h"

#include "core/log.h"

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

/* >>context */

typedef struct span {
    const char *p;
    size_t n;
} span;

typedef struct raw_sample {
    double t;         /* in the file's unit (s, ms or us), not re-based */
    float x, y, conf; /* x, y normalised; EyeLink stores pixels until the screen size is known */
    float tx, ty;     /* direction, tan(theta_x), tan(theta_y) (gaze.h's dir); NaN: none */
    bool valid;
    long line;        /* source line: messages, and the tie-break that keeps the Tobii sort stable */
} raw_sample;

typedef struct pctx {
    const char *name;  /* file name for messages */
    const char *text;  /* the whole file, BOM skipped */
    size_t size;
    gaze_load_desc desc;
    raw_sample *raw;
    int n, cap;
    double unit;       /* seconds per file time unit */
    const char *unit_name;
    bool sorted_input; /* false: the format interleaves streams, sort by time instead of checking */
    int screen_w, screen_h;
    double tan_per_x, tan_per_y; /* the recording's pinhole frame (gaze.h), 0 = unknown */
    bool has_dir;                /* some sample has a direction */
    char geometry[160];
} pctx;

/* `got` text for messages: log_quote's, at most 40 bytes; "nothing" when n == 0. Returns buf (or
 * a static string). */
const char *gaze_snip(char *buf, size_t cap, const char *p, size_t n);
/* Logs `<name>:<line>:<col>: <message>` and returns FS_ERR_GAZE. */
fs_status gaze_fail(const pctx *c, long line, long col, const char *fmt, ...) FS_PRINTF(4, 5);
fs_status gaze_no_memory(const pctx *c);
const char *gaze_eye_name(gaze_eye e);

/* >>text */

typedef struct line_it {
    const char *p, *end;
    long no; /* number of the line last returned, 1-based */
} line_it;

/* Next line without its "\n" or "\r\n"; false at the end of the text. */
bool gaze_next_line(line_it *it, span *line);

static inline bool gaze_is_blank_char(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
static inline bool gaze_is_digit(char c) { return c >= '0' && c <= '9'; }
static inline bool gaze_tok_is(span t, const char *word) { return t.n == strlen(word) && memcmp(t.p, word, t.n) == 0; }

bool gaze_is_blank(span s);
span gaze_trim(span s);
bool gaze_starts_with(span s, const char *pre);
/* ASCII case-insensitive comparison of a[0..n) with the string b. */
bool gaze_ieq(const char *a, size_t n, const char *b);

typedef enum num_result { NUM_OK, NUM_BAD, NUM_NONFINITE } num_result;

/* A decimal number `[+-]digits[.digits][e[+-]digits]`, blanks around allowed. nan, inf and hex
 * floats, which strtod would take, are refused (NUM_NONFINITE for nan/inf and for overflow). */
num_result gaze_parse_num(span s, double *out);
/* Whitespace-separated tokens (EyeLink, detection). */
bool gaze_next_tok(const char **pp, const char *end, span *tok);

/* >>samples */

/* Appends a raw sample; with c->sorted_input, time going backwards is an error at (line, col). */
fs_status gaze_push(pctx *c, long line, long col, double t, double x, double y, double conf, bool valid);
/* Gives the last sample pushed a direction (tan(theta_x), tan(theta_y), theta_y up). */
void gaze_set_dir(pctx *c, double tx, double ty);
/* Sort (if the format needs it), re-base, average repeated timestamps, fill the held gaze of
 * invalid samples. Takes c->n >= 1. */
fs_status gaze_finish(pctx *c, gaze_format fmt, gaze_trace *out);

/* >>readers (each fills out from c->text, or fails with a message) */

fs_status gaze_parse_csv(pctx *c, gaze_trace *out);     /* gaze_csv.c */
fs_status gaze_parse_pupil(pctx *c, gaze_trace *out);   /* gaze_csv.c */
fs_status gaze_parse_eyelink(pctx *c, gaze_trace *out); /* gaze_eyelink.c */
fs_status gaze_parse_tobii(pctx *c, gaze_trace *out);   /* gaze_tobii.c */
fs_status gaze_parse_eyenav(pctx *c, gaze_trace *out);  /* gaze_eyenav.c: the eye-in-head gaze */

/* CSV headers, also used by format detection (gaze_csv.c). */
/* The header line of a CSV file: the first line that is neither blank nor a '#' comment. */
bool gaze_csv_header(line_it *it, span *header);
/* 0-based index of the column called `name` in a header line, -1 if none, -2 if twice (*second:
 * the index of the second one). */
int gaze_csv_header_col(span header, const char *name, int *second);
/* One CSV field from *pp, up to the next ',' or the end (where *pp is left). Blanks around are
 * trimmed; a field in double quotes may hold commas ("" inside stays as is). False on an
 * unterminated quote. */
bool gaze_csv_field(const char **pp, const char *end, span *f);
/* True for an EyeNavGS header (columns ViewIndex, QuaternionW, GazeQW and Timestamp; gaze_eyenav.c). */
bool gaze_eyenav_header(span header);

#endif
