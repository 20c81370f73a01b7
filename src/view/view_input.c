/* view_input.c: key bindings and the --script parser of the viewer (pure C). */
#include "view/view_input.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/config.h"
#include "core/file_read.h"
#include "core/grow.h"
#include "core/log.h"

/* >>keys */
static const struct {
    const char *name;
    view_action action;
    const char *help;
} k_bindings[] = {
    {"A", VIEW_ACT_ALPHA_NEXT, "next alpha mode (the left-hand side in a split)"},
    {"T", VIEW_ACT_TAA, "TAA on/off"},
    {"F", VIEW_ACT_FOVEATION, "foveation on/off"},
    {"L", VIEW_ACT_LAYOUT_NEXT, "ring layout: the run's, auto, aggressive, off"},
    {"LEFT_BRACKET", VIEW_ACT_BIAS_DOWN, "mip bias -0.5 on every ring"},
    {"RIGHT_BRACKET", VIEW_ACT_BIAS_UP, "mip bias +0.5 on every ring"},
    {"O", VIEW_ACT_OVERLAY, "ring borders and gaze marker on/off"},
    {"D", VIEW_ACT_RING_LOD, "ring LOD on/off: fewer, larger leaf cards in the outer rings (--ring-lod)"},
    {"C", VIEW_ACT_FREEZE, "freeze the camera (gaze and time go on)"},
    {"H", VIEW_ACT_RESET_HISTORY, "reset the TAA history"},
    {"S", VIEW_ACT_SPLIT, "split screen on/off (left: the mode, right: --split's second)"},
    {"M", VIEW_ACT_SPLIT_NEXT, "next alpha mode on the right-hand side"},
    {"R", VIEW_ACT_RECORD, "start/stop recording the gaze (fovsim CSV)"},
    {"P", VIEW_ACT_CAPTURE, "capture the frame (EXR, next to the recording)"},
    {"SPACE", VIEW_ACT_PAUSE, "pause/resume time (camera, replayed trace, recording)"},
    {"N", VIEW_ACT_STEP, "one frame forward while paused"},
    {"RIGHT", VIEW_ACT_STEP, NULL},
    {"ESCAPE", VIEW_ACT_QUIT, "quit (a recording is kept)"},
    {"Q", VIEW_ACT_QUIT, NULL},
};

view_action view_key_action(const char *name)
{
    for (size_t i = 0; i < sizeof k_bindings / sizeof k_bindings[0]; i++)
        if (!strcasecmp(name, k_bindings[i].name))
            return k_bindings[i].action;
    return VIEW_ACT_NONE;
}

const char *view_key_help(void)
{
    static char buf[2048];
    if (buf[0])
        return buf;
    int o = 0;
    for (size_t i = 0; i < sizeof k_bindings / sizeof k_bindings[0]; i++) {
        if (!k_bindings[i].help)
            continue;
        const char *shown = !strcmp(k_bindings[i].name, "LEFT_BRACKET")    ? "["
                            : !strcmp(k_bindings[i].name, "RIGHT_BRACKET") ? "]"
                            : !strcmp(k_bindings[i].name, "N")             ? "N, RIGHT"
                            : !strcmp(k_bindings[i].name, "ESCAPE")        ? "ESC, Q"
                                                                           : k_bindings[i].name;
        o += snprintf(buf + o, sizeof buf - (size_t)o, "  %-10s %s\n", shown, k_bindings[i].help);
    }
    return buf;
}

/* >>script */
/* Number, optionally followed by `suffix`; *has_suffix tells whether it was. */
static bool parse_num(const char *tok, float *out, bool *has_suffix, const char *suffix)
{
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    if (errno || end == tok || !isfinite(v))
        return false;
    *has_suffix = *end != '\0';
    if (*has_suffix && strcmp(end, suffix) != 0)
        return false;
    *out = (float)v;
    return true;
}

static fs_status bad(const char *name, int line, const char *what, const char *got)
{
    log_error("%s:%d: expected %s, got '%s'", name, line, what, got);
    return FS_ERR_USAGE;
}

/* One line (already stripped of its comment) into *ev; *frame is the current `frame N`.
 * Returns FS_OK with ev->line == 0 for a line without an event (blank, `frame`). */
static fs_status parse_line(char *text, const char *name, int line, int *frame, view_event *ev)
{
    char *save = NULL, *tok[4];
    int n = 0;
    char orig[256];
    snprintf(orig, sizeof orig, "%s", text);
    for (char *t = strtok_r(text, " \t\r", &save); t; t = strtok_r(NULL, " \t\r", &save)) {
        if (n == 4)
            return bad(name, line, "at most three fields", orig);
        tok[n++] = t;
    }
    memset(ev, 0, sizeof *ev);
    if (n == 0)
        return FS_OK;
    ev->frame = *frame;
    const char *cmd = tok[0];
    if (!strcmp(cmd, "frame")) {
        char *end;
        errno = 0;
        long f = n == 2 ? strtol(tok[1], &end, 10) : -1;
        if (n != 2 || errno || end == tok[1] || *end || f < 0 || f > MAX_FRAMES)
            return bad(name, line, "'frame N' with N a frame number in [0, MAX_FRAMES]", orig);
        if (f < *frame) {
            char what[96];
            snprintf(what, sizeof what, "a frame number >= %d (frames do not go backwards)", *frame);
            return bad(name, line, what, orig);
        }
        *frame = (int)f;
        return FS_OK;
    }
    if (!strcmp(cmd, "move")) {
        bool px0 = false, px1 = false;
        if (n != 3 || !parse_num(tok[1], &ev->x, &px0, "px") || !parse_num(tok[2], &ev->y, &px1, "px") || px0 != px1)
            return bad(name, line, "'move X Y' (normalised, 0..1) or 'move Xpx Ypx' (window pixels)", orig);
        if (!px0 && (ev->x < 0.0f || ev->x > 1.0f || ev->y < 0.0f || ev->y > 1.0f))
            return bad(name, line, "normalised coordinates in [0, 1] (pixels are written 40px 30px)", orig);
        ev->kind = px0 ? VIEW_EV_MOVE_PX : VIEW_EV_MOVE;
    } else if (!strcmp(cmd, "key")) {
        if (n != 2 || view_key_action(tok[1]) == VIEW_ACT_NONE)
            return bad(name, line, "'key NAME' with a key the viewer binds (A, T, F, L, LEFT_BRACKET, "
                                   "RIGHT_BRACKET, O, C, H, S, M, R, P, SPACE, N, RIGHT, ESCAPE, Q)", orig);
        ev->kind = VIEW_EV_KEY;
        for (int i = 0; tok[1][i] && i < (int)sizeof ev->key - 1; i++)
            ev->key[i] = (char)toupper((unsigned char)tok[1][i]);
    } else if (!strcmp(cmd, "resize")) {
        char *e1, *e2;
        long w = n == 3 ? strtol(tok[1], &e1, 10) : 0, h = n == 3 ? strtol(tok[2], &e2, 10) : 0;
        if (n != 3 || *e1 || *e2 || w < 16 || h < 16 || w > MAX_DISPLAY_SIZE || h > MAX_DISPLAY_SIZE)
            return bad(name, line, "'resize W H' with a window size in [16, MAX_DISPLAY_SIZE]", orig);
        ev->kind = VIEW_EV_RESIZE;
        ev->x = (float)w;
        ev->y = (float)h;
    } else if (!strcmp(cmd, "capture") || !strcmp(cmd, "quit") || !strcmp(cmd, "leave")) {
        if (n != 1)
            return bad(name, line, "no argument after the command", orig);
        ev->kind = !strcmp(cmd, "capture") ? VIEW_EV_CAPTURE : !strcmp(cmd, "quit") ? VIEW_EV_QUIT : VIEW_EV_LEAVE;
    } else {
        return bad(name, line, "an event: frame, move, leave, resize, key, capture or quit", orig);
    }
    ev->line = line;
    return FS_OK;
}

fs_status view_script_parse(const char *text, long size, const char *name, view_script *out)
{
    memset(out, 0, sizeof *out);
    snprintf(out->path, sizeof out->path, "%s", name);
    int cap = 0, frame = 0, line = 0;
    fs_status st = FS_OK;
    for (long pos = 0; pos < size && st == FS_OK; line++) {
        long end = pos;
        while (end < size && text[end] != '\n')
            end++;
        char buf[256];
        long len = end - pos;
        if (len >= (long)sizeof buf) {
            log_error("%s:%d: expected a line of at most %d characters, got %ld", name, line + 1,
                      (int)sizeof buf - 1, len);
            st = FS_ERR_USAGE;
            break;
        }
        memcpy(buf, text + pos, (size_t)len);
        buf[len] = '\0';
        char *hash = strchr(buf, '#');
        if (hash)
            *hash = '\0';
        pos = end + 1;
        view_event ev;
        st = parse_line(buf, name, line + 1, &frame, &ev);
        if (st != FS_OK || ev.line == 0)
            continue;
        if (!FS_GROW_INT(out->events, cap, out->count + 1)) {
            st = FS_ERR_NOMEM;
            break;
        }
        out->events[out->count++] = ev;
    }
    if (st != FS_OK)
        view_script_free(out);
    return st;
}

fs_status view_script_load(const char *path, view_script *out)
{
    memset(out, 0, sizeof *out);
    char *text = NULL;
    size_t size = 0;
    fs_status st = file_read_all(path, (size_t)16 << 20, "a viewer script", FS_ERR_USAGE, &text, &size);
    if (st == FS_OK)
        st = view_script_parse(text, (long)size, path, out);
    free(text);
    return st;
}

void view_script_free(view_script *s)
{
    free(s->events);
    memset(s, 0, sizeof *s);
}
