/* test_exr_tools.c: files from exr_write_file read by tools nobody here wrote: exrheader and
 * exrinfo (Debian package openexr) and oiiotool (Debian package openimageio-tools). A missing
 * tool is a failure naming the package, not a skip: CI installs them. */
#include <stdbool.h>
#include <sys/wait.h>

#include "output/exr_write.h"
#include "test.h"

#define W 40
#define H 24

typedef struct tool_run {
    int status; /* exit status, or -1 when it did not exit normally */
    char out[16384];
} tool_run;

static bool have_tool(const char *tool, const char *package)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", tool);
    if (system(cmd) == 0)
        return true;
    fprintf(stderr, "%s: CHECK failed: '%s' is not installed: install the Debian package '%s'\n",
            test_cur_name_, tool, package);
    test_cur_failed_ = 1;
    return false;
}

/* Runs `cmd` through the shell, keeping stdout and stderr together. */
static void run_tool(const char *cmd, tool_run *r)
{
    char full[1400];
    snprintf(full, sizeof full, "%s 2>&1", cmd);
    r->status = -1;
    r->out[0] = '\0';
    FILE *p = popen(full, "r");
    if (!p)
        return;
    size_t n = fread(r->out, 1, sizeof r->out - 1, p);
    r->out[n] = '\0';
    int ws = pclose(p);
    r->status = (ws != -1 && WIFEXITED(ws)) ? WEXITSTATUS(ws) : -1;
    if (r->status != 0)
        fprintf(stderr, "  `%s` exited with %d:\n%s\n", cmd, r->status, r->out);
}

/* The frame: caller's channel order on purpose not sorted, layered names as in comparison
 * frames, and a channel of values a half cannot hold. Known min/max per channel below. */
static const char *const k_channels[] = {"coverage", "R", "G", "B", "A",
                                         "foveated.R", "ring.id", "hazard"};
enum { NCH = sizeof k_channels / sizeof k_channels[0] };
static const double k_min[NCH] = {0.0, 0.0, 0.5, -0.25, 1.0, 0.0, 0.0, -65504.0};
static const double k_max[NCH] = {1.0, 1.0, 0.5, 2.0, 1.0, 0.75, 3.0, 65504.0};

static const char *write_frame(void)
{
    static char path[1100];
    snprintf(path, sizeof path, "%s/exr_tools_frame.0007.exr", test_out_dir());
    exr_image img;
    if (!exr_image_init(&img, W, H))
        return NULL;
    float *p[NCH];
    for (int c = 0; c < NCH; c++)
        p[c] = exr_image_add_channel(&img, k_channels[c]);
    const float hazards[] = {NAN, INFINITY, -INFINITY, 1e9f, -70000.0f, 0.5f};
    for (int i = 0; i < W * H; i++) {
        p[0][i] = (float)(i % 2);                      /* coverage 0/1 */
        p[1][i] = (float)i / (float)(W * H - 1);       /* R 0..1 */
        p[2][i] = 0.5f;                                /* G */
        p[3][i] = -0.25f + 0.25f * (float)(i % 10);    /* B -0.25..2 */
        p[4][i] = 1.0f;                                /* A */
        p[5][i] = 0.25f * (float)(i % 4);              /* foveated.R 0..0.75 */
        p[6][i] = (float)((i / W) % 4);                /* ring.id 0..3 */
        p[7][i] = hazards[i % 6];                      /* hazard: clamped to ±65504 */
    }
    exr_image_set_int(&img, "fovsim:frame", 7);
    exr_image_set_float(&img, "fovsim:time", 0.125f);
    exr_image_set_v2f(&img, "fovsim:gaze_norm", 0.25f, -0.5f);
    exr_image_set_string(&img, "fovsim:renderer", "fovsim-tools-test");
    fs_status st = exr_write_file(path, &img, EXR_COMPRESS_ZIP);
    exr_image_free(&img);
    return st == FS_OK ? path : NULL;
}

TEST(exrheader_reads_frame)
{
    if (!have_tool("exrheader", "openexr"))
        return;
    const char *path = write_frame();
    CHECK(path != NULL);
    if (!path)
        return;
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "exrheader '%s'", path);
    static tool_run r;
    run_tool(cmd, &r);
    CHECK(r.status == 0);
    CHECK(strstr(r.out, "fovsim:frame (type int): 7") != NULL);
    CHECK(strstr(r.out, "fovsim:renderer (type string): \"fovsim-tools-test\"") != NULL);
    CHECK(strstr(r.out, "fovsim:gaze_norm (type v2f): (0.25 -0.5)") != NULL);
    CHECK(strstr(r.out, "fovsim:time (type float): 0.125") != NULL);
    CHECK(strstr(r.out, "foveated.R, 16-bit floating-point") != NULL);
    CHECK(strstr(r.out, "zip") != NULL);
    CHECK(strstr(r.out, "increasing y") != NULL);
    CHECK(strstr(r.out, "dataWindow (type box2i): (0 0) - (39 23)") != NULL);
}

TEST(exrinfo_strict_reads_frame)
{
    if (!have_tool("exrinfo", "openexr"))
        return;
    const char *path = write_frame();
    CHECK(path != NULL);
    if (!path)
        return;
    char cmd[1200];
    /* -s: strict header validation; -a: all metadata. */
    snprintf(cmd, sizeof cmd, "exrinfo -s -v -a '%s'", path);
    static tool_run r;
    run_tool(cmd, &r);
    CHECK(r.status == 0);
    CHECK(strstr(r.out, "fovsim:frame: int 7") != NULL);
    CHECK(strstr(r.out, "'hazard': half") != NULL);
    CHECK(strstr(r.out, "'coverage': half") != NULL);
}

TEST(oiiotool_info)
{
    if (!have_tool("oiiotool", "openimageio-tools"))
        return;
    const char *path = write_frame();
    CHECK(path != NULL);
    if (!path)
        return;
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "oiiotool --info -v '%s'", path);
    static tool_run r;
    run_tool(cmd, &r);
    CHECK(r.status == 0);
    CHECK(strstr(r.out, "40 x   24, 8 channel, half openexr") != NULL);
    CHECK(strstr(r.out, "fovsim:frame: 7") != NULL);
    CHECK(strstr(r.out, "fovsim:renderer: \"fovsim-tools-test\"") != NULL);
}

/* The numbers after `label` on one line of `out`, into v[]; returns how many. */
static int parse_row(const char *out, const char *label, double *v, int cap)
{
    const char *s = strstr(out, label);
    if (!s)
        return 0;
    s += strlen(label);
    int n = 0;
    while (n < cap) {
        char *end;
        double x = strtod(s, &end);
        if (end == s)
            break;
        v[n++] = x;
        s = end;
    }
    return n;
}

/* oiiotool lists channels in its own order: R, G, B, A first. Maps its column to ours. */
static bool oiio_channel_order(const char *info, int col_to_ch[NCH])
{
    const char *s = strstr(info, "channel list: ");
    if (!s)
        return false;
    s += strlen("channel list: ");
    for (int col = 0; col < NCH; col++) {
        size_t len = strcspn(s, ",\n");
        col_to_ch[col] = -1;
        for (int c = 0; c < NCH; c++)
            if (strlen(k_channels[c]) == len && strncmp(s, k_channels[c], len) == 0)
                col_to_ch[col] = c;
        if (col_to_ch[col] < 0)
            return false;
        s += len;
        if (*s == ',')
            s += 2;
    }
    return true;
}

TEST(oiiotool_stats)
{
    if (!have_tool("oiiotool", "openimageio-tools"))
        return;
    const char *path = write_frame();
    CHECK(path != NULL);
    if (!path)
        return;
    char cmd[1200];
    static tool_run info, stats;
    snprintf(cmd, sizeof cmd, "oiiotool --info -v '%s'", path);
    run_tool(cmd, &info);
    snprintf(cmd, sizeof cmd, "oiiotool --stats '%s'", path);
    run_tool(cmd, &stats);
    CHECK(info.status == 0 && stats.status == 0);
    int col_to_ch[NCH];
    bool order_ok = oiio_channel_order(info.out, col_to_ch);
    CHECK(order_ok);
    if (!order_ok)
        return;

    double nan_count[NCH], inf_count[NCH], finite[NCH], mn[NCH], mx[NCH];
    CHECK(parse_row(stats.out, "NanCount:", nan_count, NCH) == NCH);
    CHECK(parse_row(stats.out, "InfCount:", inf_count, NCH) == NCH);
    CHECK(parse_row(stats.out, "FiniteCount:", finite, NCH) == NCH);
    CHECK(parse_row(stats.out, "Stats Min:", mn, NCH) == NCH);
    CHECK(parse_row(stats.out, "Stats Max:", mx, NCH) == NCH);
    for (int col = 0; col < NCH; col++) {
        int c = col_to_ch[col];
        CHECK(nan_count[col] == 0.0);
        CHECK(inf_count[col] == 0.0);
        CHECK(finite[col] == (double)(W * H));
        CHECK_NEAR(mn[col], k_min[c], 1e-6);
        CHECK_NEAR(mx[col], k_max[c], 1e-6);
    }
}

/* The other direction: a 32-bit float file written by oiiotool reads back through
 * exr_read_file with exact values and typed attributes. */
TEST(reads_oiiotool_float_file)
{
    if (!have_tool("oiiotool", "openimageio-tools"))
        return;
    char path[1100], cmd[1400];
    snprintf(path, sizeof path, "%s/exr_tools_from_oiio.exr", test_out_dir());
    snprintf(cmd, sizeof cmd,
             "oiiotool --pattern constant:color=0.25,-2,1000.5 9x7 3 -d float "
             "--attrib fovsim:frame 12 --attrib fovsim:time 0.5 --sattrib fovsim:renderer oiio "
             "-o '%s'",
             path);
    static tool_run r;
    run_tool(cmd, &r);
    CHECK(r.status == 0);
    exr_image img;
    CHECK(exr_read_file(path, &img) == FS_OK);
    CHECK(img.width == 9 && img.height == 7 && img.channel_count == 3);
    static const char *names[] = {"R", "G", "B"};
    static const float want[] = {0.25f, -2.0f, 1000.5f};
    for (int c = 0; c < 3; c++) {
        const float *p = exr_image_channel(&img, names[c]);
        CHECK(p != NULL);
        int bad = 0;
        for (int i = 0; p && i < 9 * 7; i++)
            bad += p[i] != want[c];
        CHECK(bad == 0);
    }
    const exr_attr *a = exr_image_attr(&img, "fovsim:frame");
    CHECK(a && a->type == FS_EXR_ATTR_INT && a->i == 12);
    a = exr_image_attr(&img, "fovsim:time");
    CHECK(a && a->type == FS_EXR_ATTR_FLOAT && a->f[0] == 0.5f);
    a = exr_image_attr(&img, "fovsim:renderer");
    CHECK(a && a->type == FS_EXR_ATTR_STRING && strcmp(a->s, "oiio") == 0);
    exr_image_free(&img);
}

int main(void)
{
    RUN(exrheader_reads_frame);
    RUN(exrinfo_strict_reads_frame);
    RUN(oiiotool_info);
    RUN(oiiotool_stats);
    RUN(reads_oiiotool_float_file);
    return test_summary();
}
