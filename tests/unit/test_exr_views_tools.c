/* test_exr_views_tools.c: a two-eye EXR of fovsim's (exr_image_join_eyes) read by tools nobody
 * here wrote: oiiotool (Debian package openimageio-tools) lists the multiView attribute and
 * extracts each eye's values exactly, exrheader (package openexr) shows the stringvector, and
 * OpenEXR's own exrmultiview, joining the same two eyes, names every channel as fovsim does.
 *
 * Without those tools the test is skipped (exit 77), unless FOVSIM_REQUIRE_OIIO is set (to
 * anything): then a missing tool fails it. scripts/setup.sh installs both packages, so CI runs it. */
#include <stdbool.h>
#include <stdlib.h>
#include <sys/wait.h>

#include "core/log.h"
#include "output/exr_write.h"
#include "test.h"

#include "exr_eyes.h"

static char g_out[32768]; /* the last tool's stdout and stderr */

/* Runs `cmd` through the shell, stdout and stderr into g_out; its exit status (-1: did not exit). */
static int run_tool(const char *cmd)
{
    char full[2400];
    snprintf(full, sizeof full, "%s 2>&1", cmd);
    g_out[0] = '\0';
    FILE *p = popen(full, "r");
    if (!p)
        return -1;
    size_t n = fread(g_out, 1, sizeof g_out - 1, p);
    g_out[n] = '\0';
    int ws = pclose(p);
    int status = (ws != -1 && WIFEXITED(ws)) ? WEXITSTATUS(ws) : -1;
    if (status != 0)
        fprintf(stderr, "  `%s` exited with %d:\n%s\n", cmd, status, g_out);
    return status;
}

/* Writes the two eyes as one multi-view file at `name` (under the test folder); its path. */
static const char *write_eyes(const char *name)
{
    exr_image left, right, both;
    make_eye(&left, 0, -0.125f);
    make_eye(&right, 1, 0.125f);
    fs_status st = exr_image_join_eyes(&both, &left, &right);
    const char *path = path_of(name);
    if (st == FS_OK)
        st = exr_write_file(path, &both, EXR_COMPRESS_ZIP);
    exr_image_free(&both);
    exr_image_free(&left);
    exr_image_free(&right);
    CHECK(st == FS_OK);
    return st == FS_OK ? path : NULL;
}

TEST(oiiotool_lists_the_views)
{
    const char *path = write_eyes("views_tools_info.exr");
    if (!path)
        return;
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "oiiotool --info -v '%s'", path);
    CHECK(run_tool(cmd) == 0);
    CHECK(strstr(g_out, "multiView: \"left\", \"right\"") != NULL);
    CHECK(strstr(g_out, "right.coverage") != NULL && strstr(g_out, "hashed.right.R") != NULL);
    CHECK(strstr(g_out, "right.fovsim:gaze: 0.125, 0.25") != NULL);
    if (strstr(g_out, "multiView") == NULL)
        fprintf(stderr, "  oiiotool said:\n%s\n", g_out);
}

/* The command docs/output.md gives for one eye: oiiotool picks its channels by name and renames
 * them to plain R, G, B, ... in a file of its own, which fovsim's reader compares, every pixel,
 * with the eye's values at half precision. The left eye's plain channels are the file's own. */
TEST(oiiotool_extracts_each_eye)
{
    const char *path = write_eyes("views_tools_eyes.exr");
    if (!path)
        return;
    static const char *const sel[2] = {
        "R,G,B,A,coverage,hashed.R=hashed.left.R,ring.id=ring.left.id",
        "R=right.R,G=right.G,B=right.B,A=right.A,coverage=right.coverage,"
        "hashed.R=hashed.right.R,ring.id=ring.right.id",
    };
    for (int e = 0; e < 2; e++) {
        char out[1200], cmd[2400];
        snprintf(out, sizeof out, "%s", path_of(e ? "views_tools_right.exr" : "views_tools_left.exr"));
        snprintf(cmd, sizeof cmd, "oiiotool '%s' --ch %s -d half -o '%s'", path, sel[e], out);
        CHECK(run_tool(cmd) == 0);
        exr_image img;
        CHECK(exr_read_file(out, &img) == FS_OK);
        CHECK(is_eye(&img, e));
        exr_image_free(&img);
    }
    /* And oiiotool's own statistics of one channel of the right eye: its min and max. */
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "oiiotool '%s' --ch right.coverage --printstats", path);
    CHECK(run_tool(cmd) == 0);
    double mn = 0, mx = 0;
    const char *s = strstr(g_out, "Stats Min: ");
    const char *t = strstr(g_out, "Stats Max: ");
    CHECK(s && t && sscanf(s + 11, "%lf", &mn) == 1 && sscanf(t + 11, "%lf", &mx) == 1);
    CHECK_NEAR(mn, exr_half_round(eye_value(1, 4, 0)), 1e-6);
    CHECK_NEAR(mx, exr_half_round(eye_value(1, 4, W * H - 1)), 1e-6);
}

TEST(exrheader_shows_the_stringvector)
{
    const char *path = write_eyes("views_tools_header.exr");
    if (!path)
        return;
    char cmd[1400];
    snprintf(cmd, sizeof cmd, "exrheader '%s'", path);
    CHECK(run_tool(cmd) == 0);
    CHECK(strstr(g_out, "multiView (type stringvector):\n    \"left\"\n    \"right\"") != NULL);
}

/* OpenEXR's exrmultiview joins the same two eyes (single-view files written by fovsim): the
 * same channel names as exr_image_join_eyes gives, and fovsim extracts both eyes from its file. */
TEST(exrmultiview_names_channels_alike)
{
    exr_image eyes[2], ours;
    char in[2][1200];
    for (int e = 0; e < 2; e++) {
        make_eye(&eyes[e], e, 0.0f);
        snprintf(in[e], sizeof in[e], "%s", path_of(e ? "views_tools_r1.exr" : "views_tools_l1.exr"));
        CHECK(exr_write_file(in[e], &eyes[e], EXR_COMPRESS_ZIP) == FS_OK);
    }
    CHECK(exr_image_join_eyes(&ours, &eyes[0], &eyes[1]) == FS_OK);
    const char *theirs_path = path_of("views_tools_exrmultiview.exr");
    char cmd[4000];
    snprintf(cmd, sizeof cmd, "exrmultiview -z zip left '%s' right '%s' '%s'", in[0], in[1],
             theirs_path);
    CHECK(run_tool(cmd) == 0);
    exr_image theirs;
    CHECK(exr_read_file(theirs_path, &theirs) == FS_OK);
    CHECK(theirs.channel_count == ours.channel_count);
    for (int c = 0; c < ours.channel_count; c++)
        if (!exr_image_channel(&theirs, ours.channel_names[c])) {
            fprintf(stderr, "  exrmultiview has no channel '%s'\n", ours.channel_names[c]);
            CHECK(false);
        }
    CHECK(exr_image_view_count(&theirs) == 2);
    for (int e = 0; e < 2; e++) {
        exr_image v;
        CHECK(exr_image_extract_view(&theirs, e ? "right" : "left", &v) == FS_OK);
        CHECK(is_eye(&v, e));
        exr_image_free(&v);
        exr_image_free(&eyes[e]);
    }
    exr_image_free(&theirs);
    exr_image_free(&ours);
}

/* Whether every tool is installed; otherwise says which package is missing. */
static bool have_tools(void)
{
    static const char *const tools[][2] = {{"oiiotool", "openimageio-tools"},
                                           {"exrheader", "openexr"},
                                           {"exrmultiview", "openexr"}};
    bool all = true;
    for (size_t k = 0; k < sizeof tools / sizeof tools[0]; k++) {
        char cmd[128];
        snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", tools[k][0]);
        if (system(cmd) != 0) {
            fprintf(stderr, "'%s' is not installed: install the Debian package '%s' "
                            "(scripts/setup.sh does)\n", tools[k][0], tools[k][1]);
            all = false;
        }
    }
    return all;
}

int main(void)
{
    if (!have_tools()) {
        if (getenv("FOVSIM_REQUIRE_OIIO")) {
            fprintf(stderr, "FOVSIM_REQUIRE_OIIO is set, so that is a failure\n");
            return 1;
        }
        fprintf(stderr, "SKIP: external EXR tools missing (set FOVSIM_REQUIRE_OIIO to fail instead)\n");
        return 77;
    }
    RUN(oiiotool_lists_the_views);
    RUN(oiiotool_extracts_each_eye);
    RUN(exrheader_shows_the_stringvector);
    RUN(exrmultiview_names_channels_alike);
    return test_summary();
}
