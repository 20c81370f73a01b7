/* test_exr.c: EXR writer/reader (src/output/exr_write.c): half conversion, channels, attributes,
 * compression, odd sizes, atomic writes, the writer thread, damaged files and multi-part files. */
#include <dirent.h>
#include <stdbool.h>
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/config.h"
#include "core/log.h"
#include "output/exr_write.h"
#include "test.h"

// >>helpers

/* A path under <test_out>/exr/. Static buffer, rotating. */
static const char *scratch(const char *name)
{
    static char buf[8][1536];
    static int k;
    static bool made;
    if (!made) {
        char dir[1100];
        snprintf(dir, sizeof dir, "%s/exr", test_out_dir());
        if (mkdir(dir, 0777) != 0 && errno != EEXIST)
            fprintf(stderr, "cannot create %s: %s\n", dir, strerror(errno));
        made = true;
    }
    k = (k + 1) & 7;
    snprintf(buf[k], sizeof buf[k], "%s/exr/%s", test_out_dir(), name);
    return buf[k];
}

/* A fresh, empty directory under the scratch dir. */
static const char *fresh_dir(const char *name)
{
    const char *dir = scratch(name);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
    if (system(cmd) != 0)
        fprintf(stderr, "cannot create %s\n", dir);
    return dir;
}

static bool file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/* Entries of `dir` (not . and ..) whose name contains `needle`. */
static int count_entries(const char *dir, const char *needle)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        if (strstr(e->d_name, needle))
            n++;
    }
    closedir(d);
    return n;
}

/* Copies the first `n` bytes of `src` to `dst`. */
static bool copy_prefix(const char *src, const char *dst, long n)
{
    FILE *in = fopen(src, "rb"), *out = fopen(dst, "wb");
    bool ok = in && out;
    for (long i = 0; ok && i < n; i++) {
        int c = fgetc(in);
        ok = c != EOF && fputc(c, out) != EOF;
    }
    if (in)
        fclose(in);
    if (out && fclose(out) != 0)
        ok = false;
    return ok;
}

/* What a value reads back as after the trip through half: NaN -> 0, clamp to ±65504, round to
 * nearest even. An independent reference: binary search over every finite half value (exact in
 * double), not bit tricks like the writer's. */
static double half_value(int k) /* k: bits of a non-negative finite half, 0..0x7bff */
{
    if (k < 0x400)
        return ldexp((double)k, -24);
    return ldexp(1.0 + (double)(k & 0x3ff) / 1024.0, (k >> 10) - 15);
}

static float half_ref(float v)
{
    if (isnan(v))
        return 0.0f;
    double a = fabs((double)v);
    if (a >= 65504.0)
        return v < 0 ? -65504.0f : 65504.0f;
    int lo = 0, hi = 0x7bff; /* half_value(lo) <= a < half_value(hi) */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (half_value(mid) <= a)
            lo = mid;
        else
            hi = mid;
    }
    double dlo = a - half_value(lo), dhi = half_value(hi) - a;
    int k = dlo < dhi ? lo : dhi < dlo ? hi : (lo % 2 == 0 ? lo : hi);
    return (float)copysign(half_value(k), (double)v);
}

/* Largest error of a correctly rounded half: half an ulp (2^-11 relative, 2^-25 absolute in the
 * subnormal range). */
static double half_tol(float v)
{
    return fabs((double)v) * (1.0 / 2048.0) + 1.0 / 33554432.0;
}

static void fill_ramp(exr_image *img, const char *name, float scale)
{
    float *p = exr_image_channel(img, name);
    for (int i = 0; i < img->width * img->height; i++)
        p[i] = (float)i * scale;
}

static uint32_t rng_state = 12345u;
static uint32_t rng(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state;
}

static float bits_to_float(uint32_t b)
{
    float f;
    memcpy(&f, &b, sizeof f);
    return f;
}

// >>image helpers

TEST(image_helpers)
{
    exr_image img;
    CHECK(!exr_image_init(&img, 0, 10));
    CHECK(!exr_image_init(&img, 10, -1));
    CHECK(!exr_image_init(&img, 1 << 20, 1 << 20));
    CHECK(exr_image_init(&img, 4, 3));
    CHECK(img.width == 4 && img.height == 3 && img.channel_count == 0);
    float *r = exr_image_add_channel(&img, "R");
    CHECK(r != NULL);
    CHECK(r && r[11] == 0.0f);
    CHECK(exr_image_add_channel(&img, "R") == NULL); /* duplicate */
    CHECK(exr_image_add_channel(&img, "") == NULL);
    char long_name[80];
    memset(long_name, 'x', sizeof long_name - 1);
    long_name[sizeof long_name - 1] = '\0';
    CHECK(exr_image_add_channel(&img, long_name) == NULL);
    CHECK(exr_image_channel(&img, "R") == r);
    CHECK(exr_image_channel(&img, "G") == NULL);
    for (int c = 1; c < EXR_MAX_CHANNELS; c++) {
        char name[16];
        snprintf(name, sizeof name, "c%d", c);
        CHECK(exr_image_add_channel(&img, name) != NULL);
    }
    CHECK(img.channel_count == EXR_MAX_CHANNELS);
    CHECK(exr_image_add_channel(&img, "one.too.many") == NULL);

    exr_image_set_int(&img, "fovsim:frame", 1);
    exr_image_set_int(&img, "fovsim:frame", 2); /* replaces */
    CHECK(img.attr_count == 1);
    CHECK(exr_image_attr(&img, "fovsim:frame") && exr_image_attr(&img, "fovsim:frame")->i == 2);
    exr_image_set_float(&img, "fovsim:frame", 0.5f); /* replaces, with another type */
    CHECK(img.attr_count == 1);
    CHECK(exr_image_attr(&img, "fovsim:frame")->type == FS_EXR_ATTR_FLOAT);
    CHECK(exr_image_attr(&img, "nope") == NULL);
    log_set_quiet_errors(true);
    for (int a = 0; a < EXR_MAX_ATTRS + 3; a++) {
        char name[32];
        snprintf(name, sizeof name, "a%d", a);
        exr_image_set_int(&img, name, a);
    }
    CHECK(img.attr_count == EXR_MAX_ATTRS); /* the rest dropped with a warning */
    char long_value[600];
    memset(long_value, 'v', sizeof long_value - 1);
    long_value[sizeof long_value - 1] = '\0';
    exr_image_set_string(&img, "a0", long_value);
    log_set_quiet_errors(false);
    CHECK(strlen(exr_image_attr(&img, "a0")->s) == sizeof img.attrs[0].s - 1);

    exr_image_free(&img);
    CHECK(img.channel_count == 0 && img.planes[0] == NULL && img.width == 0);
    exr_image_free(&img); /* no-op on a zeroed image */
    exr_image_free(NULL);
}

// >>values

TEST(round_trip_values)
{
    const int w = 7, h = 5;
    static const char *names[] = {"R", "G", "B", "A", "coverage", "hashed.R"};
    const int nch = 6;
    exr_image img;
    CHECK(exr_image_init(&img, w, h));
    for (int c = 0; c < nch; c++)
        CHECK(exr_image_add_channel(&img, names[c]) != NULL);
    const float specials[] = {0.0f,     1.0f,     0.1f,      1e-5f,     70000.0f, -70000.0f,
                              NAN,      INFINITY, -INFINITY, -0.5f,     65504.0f, 65519.0f,
                              6.1e-5f,  3e-8f,    -1e-7f,    0.333333f, 2048.5f,  -1.0f};
    const int ns = (int)(sizeof specials / sizeof specials[0]);
    for (int c = 0; c < nch; c++) {
        float *p = img.planes[c];
        for (int i = 0; i < w * h; i++)
            p[i] = specials[(i + c * 5) % ns] * (c == 5 ? -1.0f : 1.0f);
    }
    const char *path = scratch("values.exr");
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_OK);

    exr_image out;
    CHECK(exr_read_file(path, &out) == FS_OK);
    CHECK(out.width == w && out.height == h);
    CHECK(out.channel_count == nch);
    /* The file's channel order is sorted by name, as EXR requires. */
    for (int c = 1; c < out.channel_count; c++)
        CHECK(strcmp(out.channel_names[c - 1], out.channel_names[c]) < 0);
    for (int c = 0; c < nch; c++) {
        const float *src = img.planes[c];
        const float *got = exr_image_channel(&out, names[c]);
        CHECK(got != NULL);
        if (!got)
            continue;
        for (int i = 0; i < w * h; i++) {
            float v = src[i];
            float g = got[i];
            CHECK(isfinite(g));
            if (isnan(v))
                CHECK(g == 0.0f);
            else if (v >= 65504.0f)
                CHECK(g == 65504.0f);
            else if (v <= -65504.0f)
                CHECK(g == -65504.0f);
            else
                CHECK_NEAR(g, v, half_tol(v));
        }
    }
    /* The named cases from the spec, at their known pixels (channel R: index i holds specials[i]). */
    const float *R = exr_image_channel(&out, "R");
    if (R) {
        CHECK(R[0] == 0.0f);
        CHECK(R[1] == 1.0f);
        CHECK(R[2] == 0.0999755859375f);
        CHECK_NEAR(R[3], 1e-5, 3e-8);
        CHECK(R[4] == 65504.0f);
        CHECK(R[5] == -65504.0f);
        CHECK(R[6] == 0.0f);
        CHECK(R[7] == 65504.0f);
        CHECK(R[8] == -65504.0f);
    }
    exr_image_free(&out);
    exr_image_free(&img);
}

/* Every float class through the file, compared bit for bit with a correctly rounded reference:
 * normals, subnormal halves, exact ties (both parities), overflow, NaN and Inf. */
TEST(half_rounding_matches_reference)
{
    const int w = 512, h = 512, n = w * h;
    exr_image img;
    CHECK(exr_image_init(&img, w, h));
    float *p = exr_image_add_channel(&img, "Y");
    if (!p) {
        exr_image_free(&img);
        return;
    }
    int i = 0;
    /* Ties and their neighbours in the normal range: the low 13 bits decide the rounding. */
    for (; i < n / 4; i++) {
        uint32_t exp = 113u + rng() % 30u; /* half exponents -14..15 */
        uint32_t kept = rng() & 0x3ffu;
        static const uint32_t low[] = {0x1000u, 0x0fffu, 0x1001u, 0u, 0x1fffu};
        uint32_t bits = (rng() & 0x80000000u) | exp << 23 | kept << 13 | low[i % 5];
        p[i] = bits_to_float(bits);
    }
    /* The same in the subnormal range (float exponents 102..112). */
    for (; i < n / 2; i++) {
        uint32_t exp = 102u + rng() % 11u;
        uint32_t shift = 126u - exp; /* bits below the half's last digit */
        uint32_t m = rng() & 0x7fffffu;
        if (i % 3 == 0)
            m = (m & ~((1u << shift) - 1u)) | (1u << (shift - 1u)); /* exact tie */
        uint32_t bits = (rng() & 0x80000000u) | exp << 23 | (m & 0x7fffffu);
        p[i] = bits_to_float(bits);
    }
    /* Spread over all bit patterns: every exponent, NaN, Inf, huge values. */
    for (int k = 0; i < n; i++, k++)
        p[i] = bits_to_float((uint32_t)k * 32771u * 547u + rng() % 97u);

    const char *path = scratch("rounding.exr");
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_NONE) == FS_OK);
    exr_image out;
    CHECK(exr_read_file(path, &out) == FS_OK);
    const float *got = exr_image_channel(&out, "Y");
    CHECK(got != NULL);
    int bad = 0;
    for (int k = 0; got && k < n; k++) {
        float want = half_ref(p[k]);
        uint32_t wb, gb;
        memcpy(&wb, &want, 4);
        memcpy(&gb, &got[k], 4);
        if (wb != gb && bad++ < 5)
            fprintf(stderr, "  pixel %d: in %a (0x%08x) want %a got %a\n", k, (double)p[k],
                    (unsigned)(memcpy(&wb, &p[k], 4), wb), (double)want, (double)got[k]);
    }
    CHECK(bad == 0);
    exr_image_free(&out);
    exr_image_free(&img);
}

// >>attributes

TEST(attributes_round_trip)
{
    exr_image img;
    CHECK(exr_image_init(&img, 3, 2));
    CHECK(exr_image_add_channel(&img, "R") != NULL);
    exr_image_set_string(&img, "fovsim:renderer", "fovsim 0.1.0 (llvmpipe: test) – ünïcode");
    exr_image_set_int(&img, "fovsim:frame", -42);
    exr_image_set_float(&img, "fovsim:time", 0.1f);
    exr_image_set_v2f(&img, "fovsim:gaze_norm", 0.25f, -1.5f);
    exr_image_set_string(&img, "fovsim:empty", "");
    /* Longer than 31 characters: needs OpenEXR's long-name flag. */
    exr_image_set_int(&img, "fovsim:a_rather_long_attribute_name_42", 7);
    const char *path = scratch("attrs.exr");
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_OK);

    exr_image out;
    CHECK(exr_read_file(path, &out) == FS_OK);
    CHECK(out.attr_count == img.attr_count); /* standard attributes are not copied */
    CHECK(exr_image_attr(&out, "compression") == NULL);
    CHECK(exr_image_attr(&out, "screenWindowWidth") == NULL);
    CHECK(exr_image_attr(&out, "pixelAspectRatio") == NULL);
    const exr_attr *a = exr_image_attr(&out, "fovsim:renderer");
    CHECK(a && a->type == FS_EXR_ATTR_STRING &&
          strcmp(a->s, "fovsim 0.1.0 (llvmpipe: test) – ünïcode") == 0);
    a = exr_image_attr(&out, "fovsim:frame");
    CHECK(a && a->type == FS_EXR_ATTR_INT && a->i == -42);
    a = exr_image_attr(&out, "fovsim:time");
    CHECK(a && a->type == FS_EXR_ATTR_FLOAT && a->f[0] == 0.1f); /* floats are stored as float */
    a = exr_image_attr(&out, "fovsim:gaze_norm");
    CHECK(a && a->type == FS_EXR_ATTR_V2F && a->f[0] == 0.25f && a->f[1] == -1.5f);
    a = exr_image_attr(&out, "fovsim:empty");
    CHECK(a && a->type == FS_EXR_ATTR_STRING && a->s[0] == '\0');
    a = exr_image_attr(&out, "fovsim:a_rather_long_attribute_name_42");
    CHECK(a && a->type == FS_EXR_ATTR_INT && a->i == 7);
    exr_image_free(&out);

    /* A name the format reserves is refused, and nothing is written. */
    exr_image_set_string(&img, "compression", "zip");
    const char *bad = scratch("attrs_reserved.exr");
    remove(bad);
    log_set_quiet_errors(true);
    CHECK(exr_write_file(bad, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO);
    log_set_quiet_errors(false);
    CHECK(!file_exists(bad));
    exr_image_free(&img);
}

// >>compression and sizes

static void check_ramp_file(const char *path, int w, int h, exr_compression_kind comp)
{
    exr_image img;
    CHECK(exr_image_init(&img, w, h));
    CHECK(exr_image_add_channel(&img, "R") && exr_image_add_channel(&img, "coverage"));
    /* Multiples of 1/64 below 2048 with <= 11 significant bits: exact in half. */
    fill_ramp(&img, "R", 1.0f / 64.0f);
    float *cov = exr_image_channel(&img, "coverage");
    for (int i = 0; i < w * h; i++)
        cov[i] = (float)((i * 7) % 5) * 0.25f;
    CHECK(exr_write_file(path, &img, comp) == FS_OK);
    exr_image out;
    CHECK(exr_read_file(path, &out) == FS_OK);
    CHECK(out.width == w && out.height == h && out.channel_count == 2);
    int bad = 0;
    for (int c = 0; c < 2 && out.channel_count == 2; c++) {
        const float *a = exr_image_channel(&img, c ? "coverage" : "R");
        const float *b = exr_image_channel(&out, c ? "coverage" : "R");
        CHECK(b != NULL);
        for (int i = 0; b && i < w * h; i++)
            bad += a[i] != b[i];
    }
    if (bad)
        fprintf(stderr, "  %s (%dx%d): %d pixels differ\n", path, w, h, bad);
    CHECK(bad == 0);
    exr_image_free(&out);
    exr_image_free(&img);
}

TEST(compressions_round_trip)
{
    check_ramp_file(scratch("zip.exr"), 40, 37, EXR_COMPRESS_ZIP);
    check_ramp_file(scratch("none.exr"), 40, 37, EXR_COMPRESS_NONE);
    check_ramp_file(scratch("piz.exr"), 40, 37, EXR_COMPRESS_PIZ);
    /* ZIP really compresses (a smooth ramp): smaller than the raw file. */
    CHECK(file_size(scratch("zip.exr")) > 0);
    CHECK(file_size(scratch("zip.exr")) < file_size(scratch("none.exr")));
}

TEST(odd_sizes)
{
    static const int sizes[][2] = {{1, 1}, {17, 33}, {33, 17}, {1, 40}, {41, 1}, {13, 16}, {5, 15}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        char name[64];
        snprintf(name, sizeof name, "odd_%dx%d.exr", sizes[k][0], sizes[k][1]);
        check_ramp_file(scratch(name), sizes[k][0], sizes[k][1], EXR_COMPRESS_ZIP);
        snprintf(name, sizeof name, "odd_%dx%d_none.exr", sizes[k][0], sizes[k][1]);
        check_ramp_file(scratch(name), sizes[k][0], sizes[k][1], EXR_COMPRESS_NONE);
    }
}

// >>atomic

static void make_frame(exr_image *img, int w, int h, float base)
{
    CHECK(exr_image_init(img, w, h));
    static const char *rgba[] = {"R", "G", "B", "A", "coverage"};
    for (int c = 0; c < 5; c++) {
        float *p = exr_image_add_channel(img, rgba[c]);
        CHECK(p != NULL);
        for (int i = 0; p && i < w * h; i++)
            p[i] = base + (float)((i + c * 3) % 64) / 64.0f;
    }
    exr_image_set_float(img, "fovsim:base", base);
}

TEST(atomic_missing_directory)
{
    const char *dir = scratch("no_such_dir");
    char cmd[1100];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK(system(cmd) == 0);
    char path[1200];
    snprintf(path, sizeof path, "%s/frame.0001.exr", dir);
    exr_image img;
    make_frame(&img, 8, 8, 0.0f);
    log_set_quiet_errors(true);
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO);
    log_set_quiet_errors(false);
    CHECK(!file_exists(path));
    CHECK(!file_exists(dir)); /* nothing created on the way */
    exr_image_free(&img);
}

TEST(atomic_no_temp_left_after_success)
{
    const char *dir = fresh_dir("atomic_ok");
    char path[1200];
    snprintf(path, sizeof path, "%s/frame.0001.exr", dir);
    exr_image img;
    make_frame(&img, 31, 9, 0.0f);
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_OK);
    CHECK(file_exists(path));
    CHECK(count_entries(dir, ".tmp") == 0);
    CHECK(count_entries(dir, "") == 1);
    /* Overwriting an existing frame also goes through a temporary name and leaves one file. */
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_NONE) == FS_OK);
    CHECK(count_entries(dir, "") == 1);
    exr_image_free(&img);
}

/* A write that fails part-way (the file-size limit stands in for a full disk: pwrite fails
 * with EFBIG instead of ENOSPC) leaves neither a temporary file nor anything at the final name,
 * and a frame already at the final name survives untouched. */
TEST(atomic_failure_midway)
{
    const char *dir = fresh_dir("atomic_fail");
    char path[1200], old_path[1200];
    snprintf(path, sizeof path, "%s/frame.0002.exr", dir);
    snprintf(old_path, sizeof old_path, "%s/frame.0003.exr", dir);
    exr_image small, big;
    make_frame(&small, 4, 4, 5.0f);
    make_frame(&big, 256, 256, 0.0f);
    CHECK(exr_write_file(old_path, &small, EXR_COMPRESS_ZIP) == FS_OK);

    struct rlimit old_lim;
    CHECK(getrlimit(RLIMIT_FSIZE, &old_lim) == 0);
    void (*old_sig)(int) = signal(SIGXFSZ, SIG_IGN);
    struct rlimit lim = old_lim;
    lim.rlim_cur = 16 * 1024; /* the header fits, the pixels (640 KB raw) do not */
    CHECK(setrlimit(RLIMIT_FSIZE, &lim) == 0);
    log_set_quiet_errors(true);
    fs_status st_new = exr_write_file(path, &big, EXR_COMPRESS_NONE);
    fs_status st_old = exr_write_file(old_path, &big, EXR_COMPRESS_NONE);
    log_set_quiet_errors(false);
    CHECK(setrlimit(RLIMIT_FSIZE, &old_lim) == 0);
    signal(SIGXFSZ, old_sig);

    CHECK(st_new == FS_ERR_IO);
    CHECK(st_old == FS_ERR_IO);
    CHECK(!file_exists(path));
    CHECK(count_entries(dir, ".tmp") == 0);
    CHECK(count_entries(dir, "") == 1);
    exr_image back;
    CHECK(exr_read_file(old_path, &back) == FS_OK);
    CHECK(back.width == 4 && exr_image_channel(&back, "R") &&
          exr_image_channel(&back, "R")[0] == 5.0f);
    exr_image_free(&back);

    /* Permission denied (only meaningful when not root: root ignores the mode). */
    if (geteuid() != 0) {
        const char *ro = fresh_dir("atomic_ro");
        CHECK(chmod(ro, 0555) == 0);
        char ro_path[1200];
        snprintf(ro_path, sizeof ro_path, "%s/frame.exr", ro);
        log_set_quiet_errors(true);
        CHECK(exr_write_file(ro_path, &small, EXR_COMPRESS_ZIP) == FS_ERR_IO);
        log_set_quiet_errors(false);
        CHECK(count_entries(ro, "") == 0);
        chmod(ro, 0755);
    }
    exr_image_free(&small);
    exr_image_free(&big);
}

/* A disk that is full before the first byte (it once deadlocked the writer): the header write fails inside
 * exr_write_header, while the Core holds its context lock. The error handler used to ask the Core
 * for the user data (exr_get_user_data takes that lock again) and the write hung for ever. The
 * file-size limit stands in for the full disk (EFBIG instead of ENOSPC, the same path); an alarm
 * turns the old hang into a failure. Both the plain call and the writer thread are tried. */
static void on_hang_alarm(int sig)
{
    (void)sig;
    static const char msg[] = "test_exr: hung (deadlock, or an open waiting on a FIFO)\n";
    if (write(2, msg, sizeof msg - 1) < 0) { /* nothing else to do */ }
    _exit(1);
}

TEST(atomic_failure_at_header)
{
    const char *dir = fresh_dir("atomic_full_at_start");
    char path[1200], path2[1200];
    snprintf(path, sizeof path, "%s/frame.0000.exr", dir);
    snprintf(path2, sizeof path2, "%s/frame.0001.exr", dir);
    exr_image img, img2;
    make_frame(&img, 16, 16, 0.0f);
    make_frame(&img2, 16, 16, 1.0f);

    struct rlimit old_lim;
    CHECK(getrlimit(RLIMIT_FSIZE, &old_lim) == 0);
    void (*old_sig)(int) = signal(SIGXFSZ, SIG_IGN);
    void (*old_alarm)(int) = signal(SIGALRM, on_hang_alarm);
    struct rlimit lim = old_lim;
    lim.rlim_cur = 8; /* not even the magic number and version fit */
    CHECK(setrlimit(RLIMIT_FSIZE, &lim) == 0);
    alarm(20);
    log_set_quiet_errors(true);
    fs_status st = exr_write_file(path, &img, EXR_COMPRESS_ZIP);
    exr_writer_desc d = {.thread_count = 2};
    exr_writer *w = exr_writer_create(&d);
    CHECK(w != NULL);
    fs_status st_sub = w ? exr_writer_submit(w, path2, &img2) : FS_ERR_IO;
    fs_status st_fin = w ? exr_writer_finish(w) : FS_ERR_IO;
    log_set_quiet_errors(false);
    alarm(0);
    CHECK(setrlimit(RLIMIT_FSIZE, &old_lim) == 0);
    signal(SIGALRM, old_alarm);
    signal(SIGXFSZ, old_sig);

    CHECK(st == FS_ERR_IO);
    CHECK(st_sub == FS_OK); /* queued; the failure comes back from finish */
    CHECK(st_fin == FS_ERR_IO);
    CHECK(!file_exists(path));
    CHECK(!file_exists(path2));
    CHECK(count_entries(dir, "") == 0); /* no 0-byte temporary file either */
    exr_image_free(&img);
    exr_image_free(&img2);
}

/* Only regular files are read (README "Limits"): a FIFO is refused at once instead of
 * blocking the open until a writer comes, a directory with one line. */
TEST(read_refuses_fifo_and_directory)
{
    const char *dir = fresh_dir("read_not_regular");
    char fifo[1200], sub[1200];
    snprintf(fifo, sizeof fifo, "%s/fifo.exr", dir);
    snprintf(sub, sizeof sub, "%s/dir.exr", dir);
    CHECK(mkfifo(fifo, 0644) == 0);
    CHECK(mkdir(sub, 0755) == 0);
    void (*old_alarm)(int) = signal(SIGALRM, on_hang_alarm);
    alarm(20);
    exr_image img;
    int parts = -1;
    log_set_quiet_errors(true);
    CHECK(exr_read_file(fifo, &img) == FS_ERR_IO);
    CHECK(exr_file_part_count(fifo, &parts) == FS_ERR_IO && parts == 0);
    CHECK(exr_read_file(sub, &img) == FS_ERR_IO);
    log_set_quiet_errors(false);
    alarm(0);
    signal(SIGALRM, old_alarm);
}

TEST(bad_images_refused)
{
    exr_image img;
    memset(&img, 0, sizeof img);
    const char *path = scratch("bad_image.exr");
    remove(path);
    log_set_quiet_errors(true);
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO); /* no size */
    CHECK(exr_image_init(&img, 4, 4));
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO); /* no channels */
    log_set_quiet_errors(false);
    CHECK(!file_exists(path));
    exr_image_free(&img);
}

// >>writer thread

static bool frame_reads_back(const char *path, int w, int h, float base)
{
    exr_image out;
    if (exr_read_file(path, &out) != FS_OK)
        return false;
    bool ok = out.width == w && out.height == h && out.channel_count == 5;
    const exr_attr *a = exr_image_attr(&out, "fovsim:base");
    ok = ok && a && a->type == FS_EXR_ATTR_FLOAT && a->f[0] == base;
    const float *g = exr_image_channel(&out, "G");
    for (int i = 0; ok && g && i < w * h; i++)
        ok = fabs(g[i] - (base + (float)((i + 3) % 64) / 64.0f)) <= half_tol(base + 1.0f);
    exr_image_free(&out);
    return ok && g;
}

/* Every channel and the attribute of make_frame(w, h, base), bit for bit (its values are exact in
 * half for 0 <= base < 64 in whole numbers). */
static bool frame_reads_back_exactly(const char *path, int w, int h, float base)
{
    exr_image want, got;
    make_frame(&want, w, h, base);
    bool ok = exr_read_file(path, &got) == FS_OK;
    ok = ok && got.width == w && got.height == h && got.channel_count == want.channel_count;
    for (int c = 0; ok && c < want.channel_count; c++) {
        const float *g = exr_image_channel(&got, want.channel_names[c]);
        ok = g && memcmp(g, want.planes[c], (size_t)w * (size_t)h * sizeof *g) == 0;
    }
    const exr_attr *a = ok ? exr_image_attr(&got, "fovsim:base") : NULL;
    ok = ok && a && a->type == FS_EXR_ATTR_FLOAT && a->f[0] == base;
    exr_image_free(&got);
    exr_image_free(&want);
    return ok;
}

static void writer_writes_all_frames(int threads)
{
    char name[64];
    snprintf(name, sizeof name, "writer_t%d", threads);
    const char *dir = fresh_dir(name);
    exr_writer *w =
        exr_writer_create(&(exr_writer_desc){.queue_depth = 2, .thread_count = threads});
    CHECK(w != NULL);
    if (!w)
        return;
    for (int f = 0; f < 10; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/frame.%04d.exr", dir, f);
        exr_image img;
        make_frame(&img, 64 + f, 48, (float)f);
        CHECK(exr_writer_submit(w, path, &img) == FS_OK);
        CHECK(img.planes[0] == NULL && img.channel_count == 0); /* ownership moved */
    }
    CHECK(exr_writer_finish(w) == FS_OK);
    for (int f = 0; f < 10; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/frame.%04d.exr", dir, f);
        CHECK(frame_reads_back(path, 64 + f, 48, (float)f));
    }
    CHECK(count_entries(dir, ".tmp") == 0);
    CHECK(count_entries(dir, ".exr") == 10);

    /* Defaults (NULL desc), nothing submitted. */
    exr_writer *w2 = exr_writer_create(NULL);
    CHECK(w2 != NULL);
    CHECK(exr_writer_finish(w2) == FS_OK);
    CHECK(exr_writer_finish(NULL) == FS_OK);
}

TEST(writer_thread_writes_all_frames_1_thread) { writer_writes_all_frames(1); }
TEST(writer_thread_writes_all_frames_4_threads) { writer_writes_all_frames(4); }

static void writer_error_is_sticky(int threads)
{
    char name[64];
    snprintf(name, sizeof name, "writer_err_t%d", threads);
    const char *dir = fresh_dir(name);
    char bad[1200];
    snprintf(bad, sizeof bad, "%s/missing_subdir/frame.0000.exr", dir);
    log_set_quiet_errors(true);

    /* Error reported by finish. */
    exr_writer *w =
        exr_writer_create(&(exr_writer_desc){.queue_depth = 2, .thread_count = threads});
    CHECK(w != NULL);
    if (!w) {
        log_set_quiet_errors(false);
        return;
    }
    exr_image img;
    make_frame(&img, 8, 8, 0.0f);
    CHECK(exr_writer_submit(w, bad, &img) == FS_OK); /* queued; fails on the thread */
    CHECK(exr_writer_finish(w) == FS_ERR_IO);

    /* Error returned by later submits, which then free the image and queue nothing. */
    w = exr_writer_create(&(exr_writer_desc){.queue_depth = 1, .thread_count = threads});
    CHECK(w != NULL);
    if (!w) {
        log_set_quiet_errors(false);
        return;
    }
    make_frame(&img, 8, 8, 0.0f);
    CHECK(exr_writer_submit(w, bad, &img) == FS_OK);
    fs_status st = FS_OK;
    int f;
    for (f = 1; f < 200 && st == FS_OK; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/after.%04d.exr", dir, f);
        make_frame(&img, 8, 8, (float)f);
        st = exr_writer_submit(w, path, &img);
        if (st != FS_OK) {
            CHECK(img.planes[0] == NULL); /* freed */
            CHECK(!file_exists(path));   /* not queued */
        } else {
            nanosleep(&(struct timespec){.tv_nsec = 2000000}, NULL);
        }
    }
    CHECK(st == FS_ERR_IO);
    make_frame(&img, 8, 8, 0.0f);
    char later[1200];
    snprintf(later, sizeof later, "%s/later.exr", dir);
    CHECK(exr_writer_submit(w, later, &img) == FS_ERR_IO);
    CHECK(exr_writer_finish(w) == FS_ERR_IO);
    CHECK(!file_exists(later));
    log_set_quiet_errors(false);
}

TEST(writer_thread_error_is_sticky_1_thread) { writer_error_is_sticky(1); }
TEST(writer_thread_error_is_sticky_4_threads) { writer_error_is_sticky(4); }

TEST(writer_desc_defaults)
{
    exr_writer_desc d = exr_writer_desc_defaults(NULL);
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    int want = cpus < 1 ? 1 : cpus > EXR_MAX_WRITER_THREADS ? EXR_MAX_WRITER_THREADS : (int)cpus;
    CHECK(d.compression == EXR_COMPRESS_ZIP);
    CHECK(d.queue_depth == EXR_QUEUE_DEPTH);
    CHECK(d.thread_count == want);
    CHECK(d.zip_level == EXR_ZIP_LEVEL_DEFAULT);
    d = exr_writer_desc_defaults(&(exr_writer_desc){.compression = EXR_COMPRESS_PIZ,
                                                    .queue_depth = 3, .thread_count = 2,
                                                    .zip_level = 9});
    CHECK(d.compression == EXR_COMPRESS_PIZ && d.queue_depth == 3 && d.thread_count == 2 &&
          d.zip_level == 9);
    d = exr_writer_desc_defaults(
        &(exr_writer_desc){.queue_depth = -1, .thread_count = 1000, .zip_level = 42});
    CHECK(d.queue_depth == EXR_QUEUE_DEPTH);
    CHECK(d.thread_count == EXR_MAX_WRITER_THREADS);
    CHECK(d.zip_level == 9);
    CHECK(exr_writer_desc_defaults(&(exr_writer_desc){.thread_count = -3}).thread_count == want);
}

/* More frames than threads and queue slots together, so submit blocks again and again and every
 * worker takes many frames; each file must still be exactly its own frame. Also a non-default
 * deflate level, which must not change a single pixel. */
TEST(writer_threads_many_frames)
{
    const char *dir = fresh_dir("writer_many");
    enum { N = 24 };
    exr_writer *w = exr_writer_create(
        &(exr_writer_desc){.queue_depth = 2, .thread_count = 3, .zip_level = 1});
    CHECK(w != NULL);
    if (!w)
        return;
    for (int f = 0; f < N; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/frame.%04d.exr", dir, f);
        exr_image img;
        make_frame(&img, 96 + f, 40 + (f * 7) % 13, (float)f);
        CHECK(exr_writer_submit(w, path, &img) == FS_OK);
        CHECK(img.planes[0] == NULL && img.channel_count == 0);
    }
    CHECK(exr_writer_finish(w) == FS_OK);
    for (int f = 0; f < N; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/frame.%04d.exr", dir, f);
        CHECK(file_exists(path));
        CHECK(frame_reads_back_exactly(path, 96 + f, 40 + (f * 7) % 13, (float)f));
    }
    CHECK(count_entries(dir, ".tmp") == 0);
    CHECK(count_entries(dir, "") == N);
}

/* A write failing on one worker while the others succeed: finish still reports it, and the frames
 * accepted before it are all complete. */
TEST(writer_threads_error_with_others_succeeding)
{
    const char *dir = fresh_dir("writer_err_mt");
    char bad[1200];
    snprintf(bad, sizeof bad, "%s/missing_subdir/frame.exr", dir);
    log_set_quiet_errors(true);

    /* The failing frame last: every submit is accepted (nothing has failed yet), the failure
     * comes while the other workers are busy with larger frames. */
    exr_writer *w = exr_writer_create(&(exr_writer_desc){.queue_depth = 8, .thread_count = 4});
    CHECK(w != NULL);
    if (!w) {
        log_set_quiet_errors(false);
        return;
    }
    exr_image img;
    for (int f = 0; f < 3; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/good.%04d.exr", dir, f);
        make_frame(&img, 300, 200, (float)f);
        CHECK(exr_writer_submit(w, path, &img) == FS_OK);
    }
    make_frame(&img, 8, 8, 0.0f);
    CHECK(exr_writer_submit(w, bad, &img) == FS_OK);
    CHECK(exr_writer_finish(w) == FS_ERR_IO);
    for (int f = 0; f < 3; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/good.%04d.exr", dir, f);
        CHECK(frame_reads_back_exactly(path, 300, 200, (float)f));
    }

    /* The failing frame first: whatever was accepted is written in full, the rest is refused. */
    w = exr_writer_create(&(exr_writer_desc){.queue_depth = 2, .thread_count = 3});
    CHECK(w != NULL);
    if (!w) {
        log_set_quiet_errors(false);
        return;
    }
    make_frame(&img, 8, 8, 0.0f);
    CHECK(exr_writer_submit(w, bad, &img) == FS_OK);
    bool accepted[12];
    for (int f = 0; f < 12; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/after.%04d.exr", dir, f);
        make_frame(&img, 64, 32, (float)f);
        fs_status st = exr_writer_submit(w, path, &img);
        CHECK(st == FS_OK || st == FS_ERR_IO);
        accepted[f] = st == FS_OK;
    }
    CHECK(exr_writer_finish(w) == FS_ERR_IO);
    for (int f = 0; f < 12; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/after.%04d.exr", dir, f);
        if (accepted[f])
            CHECK(frame_reads_back_exactly(path, 64, 32, (float)f));
        else
            CHECK(!file_exists(path));
    }
    CHECK(count_entries(dir, ".tmp") == 0);
    log_set_quiet_errors(false);
}

/* Frames queued for one path are written one at a time, in order: the last one submitted is what
 * stays, and no temporary file is left behind. */
TEST(writer_threads_same_path_in_order)
{
    const char *dir = fresh_dir("writer_same_path");
    char path[1200];
    snprintf(path, sizeof path, "%s/frame.exr", dir);
    exr_writer *w = exr_writer_create(&(exr_writer_desc){.queue_depth = 4, .thread_count = 4});
    CHECK(w != NULL);
    if (!w)
        return;
    for (int f = 0; f < 12; f++) {
        exr_image img;
        /* Later frames are smaller: written concurrently, they would finish first. */
        make_frame(&img, 16 + (11 - f) * 40, 60, (float)f);
        CHECK(exr_writer_submit(w, path, &img) == FS_OK);
        /* Other paths in between, so the queue mixes free and blocked jobs. */
        char other[1300];
        snprintf(other, sizeof other, "%s/other.%04d.exr", dir, f);
        make_frame(&img, 16, 16, (float)f);
        CHECK(exr_writer_submit(w, other, &img) == FS_OK);
    }
    CHECK(exr_writer_finish(w) == FS_OK);
    CHECK(frame_reads_back_exactly(path, 16, 60, 11.0f));
    for (int f = 0; f < 12; f++) {
        char other[1300];
        snprintf(other, sizeof other, "%s/other.%04d.exr", dir, f);
        CHECK(frame_reads_back_exactly(other, 16, 16, (float)f));
    }
    CHECK(count_entries(dir, ".tmp") == 0);
    CHECK(count_entries(dir, "") == 13);
}

// >>multi-part

/* Value of pixel i of channel c of part `part` in make_compare frames: exact in half for whole
 * `base` in 0..63 (multiples of 1/64 below 128). */
static float compare_value(int part, int c, int i, float base)
{
    return base + (float)((i * (part + 1) + c * 7) % 64) / 64.0f;
}

/* The layer channels of a comparison frame for `nmodes` alpha modes, in a deliberately unsorted
 * order: per mode R, G, B, A, coverage, error; then reference.*, ring.id. */
static const char *const k_modes[] = {"traditional", "stochastic", "hashed",   "a2c",    "hashed_a2c",
                                      "castano",     "mipscale",   "hashed_x", "mode_9"};
static int layer_names(int nmodes, char names[][64])
{
    static const char *const per_mode[] = {"R", "G", "B", "A", "coverage", "error"};
    int n = 0;
    for (int m = 0; m < nmodes; m++)
        for (int k = 0; k < 6; k++)
            snprintf(names[n++], 64, "%s.%s", k_modes[m], per_mode[k]);
    static const char *const ref[] = {"reference.R", "reference.G", "reference.B", "reference.A",
                                      "reference.coverage", "ring.id"};
    for (int k = 0; k < 6; k++)
        snprintf(names[n++], 64, "%s", ref[k]);
    return n;
}

/* A comparison frame as `fovsim compare` writes it: part 0 "compare", a cols x 1 grid of w x h
 * cells in R, G, B, A; part 1 "layers", w x h with the layer channels of `nmodes` modes. Each
 * part has its own attributes besides a shared frame number. */
static void make_compare(exr_image *img, int w, int h, int cols, int nmodes, float base)
{
    CHECK(exr_image_init(img, cols * w, h));
    CHECK(exr_image_set_part_name(img, "compare"));
    static const char *rgba[] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; c++) {
        float *p = exr_image_add_channel(img, rgba[c]);
        CHECK(p != NULL);
        for (int i = 0; p && i < cols * w * h; i++)
            p[i] = compare_value(0, c, i, base);
    }
    exr_image_set_int(img, "fovsim:frame", (int)base);
    exr_image_set_string(img, "fovsim:view", "side by side");

    exr_image layers;
    CHECK(exr_image_init(&layers, w, h));
    CHECK(exr_image_set_part_name(&layers, "layers"));
    char names[EXR_MAX_CHANNELS][64];
    int n = layer_names(nmodes, names);
    for (int c = 0; c < n; c++) {
        float *p = exr_image_add_channel(&layers, names[c]);
        CHECK(p != NULL);
        for (int i = 0; p && i < w * h; i++)
            p[i] = compare_value(1, c, i, base);
    }
    exr_image_set_int(&layers, "fovsim:frame", (int)base);
    exr_image_set_v2f(&layers, "fovsim:gaze", 0.25f, 0.75f);
    exr_image_set_float(&layers, "fovsim:base", base);
    CHECK(exr_image_append_part(img, &layers));
    CHECK(layers.next_part == NULL && layers.planes[0] == NULL); /* moved */
}

/* Part `part` of a make_compare file, every pixel and attribute exactly. */
static bool compare_part_reads_back(const char *path, int part, int w, int h, int cols,
                                    int nmodes, float base)
{
    exr_image got;
    if (exr_read_part(path, part, &got) != FS_OK)
        return false;
    bool ok = got.next_part == NULL;
    char names[EXR_MAX_CHANNELS][64];
    int n = 4;
    if (part == 0) {
        snprintf(names[0], 64, "R");
        snprintf(names[1], 64, "G");
        snprintf(names[2], 64, "B");
        snprintf(names[3], 64, "A");
        ok = ok && strcmp(got.part_name, "compare") == 0 && got.width == cols * w &&
             got.height == h;
        const exr_attr *a = exr_image_attr(&got, "fovsim:view");
        ok = ok && a && a->type == FS_EXR_ATTR_STRING && strcmp(a->s, "side by side") == 0;
        ok = ok && !exr_image_attr(&got, "fovsim:gaze") && got.attr_count == 2;
    } else {
        n = layer_names(nmodes, names);
        ok = ok && strcmp(got.part_name, "layers") == 0 && got.width == w && got.height == h;
        const exr_attr *a = exr_image_attr(&got, "fovsim:gaze");
        ok = ok && a && a->type == FS_EXR_ATTR_V2F && a->f[0] == 0.25f && a->f[1] == 0.75f;
        a = exr_image_attr(&got, "fovsim:base");
        ok = ok && a && a->type == FS_EXR_ATTR_FLOAT && a->f[0] == base;
        ok = ok && !exr_image_attr(&got, "fovsim:view") && got.attr_count == 3;
    }
    const exr_attr *fr = exr_image_attr(&got, "fovsim:frame");
    ok = ok && fr && fr->type == FS_EXR_ATTR_INT && fr->i == (int)base;
    ok = ok && got.channel_count == n;
    /* Sorted by name in the file, as EXR requires. */
    for (int c = 1; ok && c < got.channel_count; c++)
        ok = strcmp(got.channel_names[c - 1], got.channel_names[c]) < 0;
    int bad = 0;
    for (int c = 0; ok && c < n; c++) {
        const float *p = exr_image_channel(&got, names[c]);
        ok = p != NULL;
        for (int i = 0; p && i < got.width * got.height; i++)
            bad += p[i] != compare_value(part, c, i, base);
    }
    if (bad)
        fprintf(stderr, "  %s part %d: %d values differ\n", path, part, bad);
    exr_image_free(&got);
    return ok && bad == 0;
}

TEST(multipart_image_chain)
{
    exr_image img;
    make_compare(&img, 5, 3, 2, 1, 0.0f);
    CHECK(exr_image_part_count(&img) == 2);
    CHECK(exr_image_part_count(NULL) == 0);
    CHECK(exr_image_part(&img, 0) == &img);
    exr_image *layers = exr_image_part(&img, 1);
    CHECK(layers && strcmp(layers->part_name, "layers") == 0 && layers->width == 5);
    CHECK(exr_image_part(&img, 2) == NULL);
    CHECK(exr_image_part(&img, -1) == NULL);
    CHECK(!exr_image_append_part(&img, &img)); /* onto itself: refused, nothing changed */
    CHECK(exr_image_part_count(&img) == 2);

    /* A chain appended to a chain keeps its order: compare, layers, x, y. */
    exr_image x, y;
    CHECK(exr_image_init(&x, 2, 2) && exr_image_set_part_name(&x, "x"));
    CHECK(exr_image_add_channel(&x, "Y") != NULL);
    CHECK(exr_image_init(&y, 1, 1) && exr_image_set_part_name(&y, "y"));
    CHECK(exr_image_add_channel(&y, "Y") != NULL);
    CHECK(exr_image_append_part(&x, &y));
    CHECK(exr_image_append_part(&img, &x));
    CHECK(x.next_part == NULL && x.planes[0] == NULL);
    CHECK(exr_image_part_count(&img) == 4);
    CHECK(exr_image_part(&img, 3) && strcmp(exr_image_part(&img, 3)->part_name, "y") == 0);

    char long_name[80];
    memset(long_name, 'p', sizeof long_name - 1);
    long_name[sizeof long_name - 1] = '\0';
    CHECK(!exr_image_set_part_name(&img, long_name));
    CHECK(strcmp(img.part_name, "compare") == 0);

    exr_image_free(&img); /* frees the whole chain (ASan checks) */
    CHECK(img.next_part == NULL && img.channel_count == 0);
}

/* Two parts of different sizes, names, channels and attributes, every compression; the part
 * count, each part exactly, part 0 through exr_read_file, and parts that do not exist. */
TEST(multipart_round_trip)
{
    static const exr_compression_kind comps[] = {EXR_COMPRESS_ZIP, EXR_COMPRESS_NONE,
                                                 EXR_COMPRESS_PIZ};
    static const char *comp_names[] = {"zip", "none", "piz"};
    for (int k = 0; k < 3; k++) {
        char name[64];
        snprintf(name, sizeof name, "multipart_%s.exr", comp_names[k]);
        const char *path = scratch(name);
        exr_image img;
        make_compare(&img, 37, 21, 3, 2, 5.0f);
        CHECK(exr_write_file(path, &img, comps[k]) == FS_OK);
        exr_image_free(&img);
        int n = 0;
        CHECK(exr_file_part_count(path, &n) == FS_OK);
        CHECK(n == 2);
        CHECK(compare_part_reads_back(path, 0, 37, 21, 3, 2, 5.0f));
        CHECK(compare_part_reads_back(path, 1, 37, 21, 3, 2, 5.0f));
        exr_image first;
        CHECK(exr_read_file(path, &first) == FS_OK);
        CHECK(strcmp(first.part_name, "compare") == 0 && first.width == 3 * 37);
        exr_image_free(&first);
    }
    const char *path = scratch("multipart_zip.exr");
    exr_image out;
    log_set_quiet_errors(true);
    CHECK(exr_read_part(path, 2, &out) == FS_ERR_IO);
    CHECK(exr_read_part(path, -1, &out) == FS_ERR_IO);
    CHECK(out.channel_count == 0 && out.planes[0] == NULL);
    int n = 7;
    CHECK(exr_file_part_count(scratch("no_such_file.exr"), &n) == FS_ERR_IO && n == 0);
    log_set_quiet_errors(false);

    /* A single-part file counts one part; its name stays empty unless one was set. */
    check_ramp_file(scratch("single_for_count.exr"), 4, 4, EXR_COMPRESS_ZIP);
    CHECK(exr_file_part_count(scratch("single_for_count.exr"), &n) == FS_OK && n == 1);
    CHECK(exr_read_file(scratch("single_for_count.exr"), &out) == FS_OK);
    CHECK(out.part_name[0] == '\0');
    exr_image_free(&out);
    exr_image img;
    make_frame(&img, 4, 4, 1.0f);
    CHECK(exr_image_set_part_name(&img, "beauty"));
    CHECK(exr_write_file(scratch("single_named.exr"), &img, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&img);
    CHECK(exr_file_part_count(scratch("single_named.exr"), &n) == FS_OK && n == 1);
    CHECK(exr_read_file(scratch("single_named.exr"), &out) == FS_OK);
    CHECK(strcmp(out.part_name, "beauty") == 0);
    CHECK(exr_image_attr(&out, "name") == NULL); /* reserved: not a custom attribute */
    exr_image_free(&out);
}

/* The largest layer part fovsim writes: 9 modes x 6 channels + reference 5 + ring.id = 60, and
 * a third part, so chains longer than two work too. */
TEST(multipart_many_channels_three_parts)
{
    const char *path = scratch("multipart_60ch.exr");
    exr_image img;
    make_compare(&img, 16, 9, 3, 9, 2.0f);
    CHECK(exr_image_part(&img, 1) && exr_image_part(&img, 1)->channel_count == 60);
    exr_image extra;
    CHECK(exr_image_init(&extra, 1, 1) && exr_image_set_part_name(&extra, "extra"));
    float *e = exr_image_add_channel(&extra, "Y");
    if (e)
        e[0] = 70000.0f; /* clamped like everywhere else */
    CHECK(exr_image_append_part(&img, &extra));
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&img);
    int n = 0;
    CHECK(exr_file_part_count(path, &n) == FS_OK && n == 3);
    CHECK(compare_part_reads_back(path, 0, 16, 9, 3, 9, 2.0f));
    CHECK(compare_part_reads_back(path, 1, 16, 9, 3, 9, 2.0f));
    exr_image out;
    CHECK(exr_read_part(path, 2, &out) == FS_OK);
    CHECK(strcmp(out.part_name, "extra") == 0 && out.width == 1 && out.height == 1);
    CHECK(exr_image_channel(&out, "Y") && exr_image_channel(&out, "Y")[0] == 65504.0f);
    exr_image_free(&out);
}

/* Part 0 smaller than part 1 in one direction and larger in the other: the shared display
 * window covers both (checked with exrinfo -s by hand), each part keeps its own data window. */
TEST(multipart_sizes_independent)
{
    const char *path = scratch("multipart_sizes.exr");
    exr_image a, b;
    CHECK(exr_image_init(&a, 4, 6) && exr_image_set_part_name(&a, "a"));
    CHECK(exr_image_init(&b, 10, 3) && exr_image_set_part_name(&b, "b"));
    float *pa = exr_image_add_channel(&a, "Y"), *pb = exr_image_add_channel(&b, "Y");
    for (int i = 0; pa && i < 24; i++)
        pa[i] = (float)i;
    for (int i = 0; pb && i < 30; i++)
        pb[i] = (float)-i;
    CHECK(exr_image_append_part(&a, &b));
    CHECK(exr_write_file(path, &a, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&a);
    exr_image out;
    CHECK(exr_read_part(path, 0, &out) == FS_OK);
    CHECK(out.width == 4 && out.height == 6 && strcmp(out.part_name, "a") == 0);
    const float *y = exr_image_channel(&out, "Y");
    CHECK(y && y[23] == 23.0f);
    exr_image_free(&out);
    CHECK(exr_read_part(path, 1, &out) == FS_OK);
    CHECK(out.width == 10 && out.height == 3 && strcmp(out.part_name, "b") == 0);
    y = exr_image_channel(&out, "Y");
    CHECK(y && y[29] == -29.0f);
    exr_image_free(&out);
}

TEST(multipart_bad_chains_refused)
{
    const char *path = scratch("multipart_bad.exr");
    remove(path);
    log_set_quiet_errors(true);
    exr_image img;
    /* An unnamed second part. */
    make_compare(&img, 4, 4, 2, 1, 0.0f);
    exr_image_part(&img, 1)->part_name[0] = '\0';
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO);
    /* An unnamed first part. */
    CHECK(exr_image_set_part_name(exr_image_part(&img, 1), "layers"));
    CHECK(exr_image_set_part_name(&img, ""));
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO);
    /* Two parts of one name. */
    CHECK(exr_image_set_part_name(&img, "layers"));
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO);
    exr_image_free(&img);
    /* A second part with no channels. */
    make_compare(&img, 4, 4, 2, 1, 0.0f);
    exr_image empty;
    CHECK(exr_image_init(&empty, 4, 4) && exr_image_set_part_name(&empty, "empty"));
    CHECK(exr_image_append_part(&img, &empty));
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_ERR_IO);
    exr_image_free(&img);
    log_set_quiet_errors(false);
    CHECK(!file_exists(path));
    CHECK(count_entries(scratch(""), ".multipart_bad.exr.tmp") == 0);
}

/* A multi-part file cut anywhere fails to read, whichever part is asked for: the cut may lie
 * in part 1's pixels, which part 0 alone never touches. */
TEST(multipart_truncated_fails)
{
    char good[1600]; /* scratch() rotates its buffers: keep a copy */
    snprintf(good, sizeof good, "%s", scratch("multipart_for_truncation.exr"));
    char cut[1600];
    snprintf(cut, sizeof cut, "%s", scratch("multipart_truncated.exr"));
    exr_image img;
    make_compare(&img, 64, 40, 2, 2, 1.0f);
    CHECK(exr_write_file(good, &img, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&img);
    long size = file_size(good);
    CHECK(size > 1000);
    const long cuts[] = {0, 4, 8, 100, 400, size / 2, size - 100, size - 8, size - 1};
    log_set_quiet_errors(true);
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        CHECK(copy_prefix(good, cut, cuts[k]));
        exr_image out;
        for (int part = 0; part < 2; part++) {
            fs_status st = exr_read_part(cut, part, &out);
            if (st != FS_ERR_IO)
                fprintf(stderr, "  cut to %ld of %ld bytes: part %d read returned %d\n", cuts[k],
                        size, part, (int)st);
            CHECK(st == FS_ERR_IO);
            CHECK(out.channel_count == 0 && out.planes[0] == NULL);
            exr_image_free(&out);
        }
        CHECK(exr_read_file(cut, &out) == FS_ERR_IO);
    }
    log_set_quiet_errors(false);
    CHECK(compare_part_reads_back(good, 0, 64, 40, 2, 2, 1.0f));
}

/* The writer thread takes the whole chain (the caller's image is zeroed, parts included) and
 * writes multi-part and single-part frames side by side. */
TEST(multipart_writer_thread)
{
    const char *dir = fresh_dir("writer_multipart");
    exr_writer *w = exr_writer_create(&(exr_writer_desc){.queue_depth = 2, .thread_count = 2});
    CHECK(w != NULL);
    if (!w)
        return;
    for (int f = 0; f < 8; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/cmp.%04d.exr", dir, f);
        exr_image img;
        if (f % 3 == 2)
            make_frame(&img, 20 + f, 10, (float)f);
        else
            make_compare(&img, 20 + f, 10, 2, 3, (float)f);
        CHECK(exr_writer_submit(w, path, &img) == FS_OK);
        CHECK(img.next_part == NULL && img.planes[0] == NULL && img.channel_count == 0);
    }
    CHECK(exr_writer_finish(w) == FS_OK);
    for (int f = 0; f < 8; f++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/cmp.%04d.exr", dir, f);
        int n = 0;
        CHECK(exr_file_part_count(path, &n) == FS_OK);
        if (f % 3 == 2) {
            CHECK(n == 1);
            CHECK(frame_reads_back_exactly(path, 20 + f, 10, (float)f));
        } else {
            CHECK(n == 2);
            CHECK(compare_part_reads_back(path, 0, 20 + f, 10, 2, 3, (float)f));
            CHECK(compare_part_reads_back(path, 1, 20 + f, 10, 2, 3, (float)f));
        }
    }
    CHECK(count_entries(dir, ".tmp") == 0);

    /* A failing multi-part frame: the error comes back, the chain is freed (ASan checks). */
    w = exr_writer_create(&(exr_writer_desc){.queue_depth = 1, .thread_count = 1});
    CHECK(w != NULL);
    if (!w)
        return;
    char bad[1200];
    snprintf(bad, sizeof bad, "%s/missing_subdir/cmp.exr", dir);
    exr_image img;
    make_compare(&img, 8, 8, 2, 1, 0.0f);
    log_set_quiet_errors(true);
    CHECK(exr_writer_submit(w, bad, &img) == FS_OK);
    CHECK(exr_writer_finish(w) == FS_ERR_IO);
    log_set_quiet_errors(false);
}

// >>damaged files

TEST(read_missing_or_damaged_files)
{
    exr_image out;
    log_set_quiet_errors(true);
    CHECK(exr_read_file(scratch("does_not_exist.exr"), &out) == FS_ERR_IO);
    CHECK(out.channel_count == 0 && out.planes[0] == NULL);

    const char *text = scratch("not_an_exr.exr");
    FILE *f = fopen(text, "w");
    CHECK(f != NULL);
    if (f) {
        fputs("this is not an EXR file\n", f);
        fclose(f);
    }
    CHECK(exr_read_file(text, &out) == FS_ERR_IO);

    const char *good = scratch("good_for_truncation.exr");
    exr_image img;
    make_frame(&img, 64, 50, 0.5f);
    CHECK(exr_write_file(good, &img, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&img);
    long size = file_size(good);
    CHECK(size > 100);
    const long cuts[] = {0, 4, 8, 100, size / 2, size - 8, size - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        const char *cut = scratch("truncated.exr");
        CHECK(copy_prefix(good, cut, cuts[k]));
        fs_status st = exr_read_file(cut, &out);
        if (st != FS_ERR_IO)
            fprintf(stderr, "  truncated to %ld of %ld bytes: read returned %d\n", cuts[k], size,
                    (int)st);
        CHECK(st == FS_ERR_IO);
        CHECK(out.channel_count == 0 && out.planes[0] == NULL);
        exr_image_free(&out);
    }
    log_set_quiet_errors(false);
    CHECK(exr_read_file(good, &out) == FS_OK);
    exr_image_free(&out);
}

TEST(half_round_equals_read_back)
{
    /* exr_half_round(v) is exactly what a file stores for v: the reference uses it so a drawn frame
     * and its cached copy give identical metrics. Normal, subnormal, tie, huge, NaN, Inf, -0. */
    static const float v[] = {0.0f, -0.0f, 1.0f, 0.1f, 1.0f / 3.0f, 0.7f, -2.5e-3f, 6.0e-8f, 3.0e-8f, 1.0e-6f,
                              2049.0f, 2051.0f, 65504.0f, 65519.0f, 1e9f, -1e9f, 1.0009765625f, 1.00048828125f,
                              NAN, INFINITY, -INFINITY, 5.96e-8f, 6.1e-5f};
    enum { N = sizeof v / sizeof v[0] };
    exr_image img, back;
    CHECK(exr_image_init(&img, N, 1));
    float *p = exr_image_add_channel(&img, "Y");
    for (int i = 0; i < N; i++)
        p[i] = v[i];
    const char *path = scratch("half_round.exr");
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_NONE) == FS_OK);
    CHECK(exr_read_file(path, &back) == FS_OK);
    const float *q = exr_image_channel(&back, "Y");
    for (int i = 0; q && i < N; i++) {
        float h = exr_half_round(v[i]);
        if (memcmp(&h, &q[i], sizeof h) != 0) {
            fprintf(stderr, "  %g: rounded %.9g, file %.9g\n", (double)v[i], (double)h, (double)q[i]);
            CHECK(false);
        }
    }
    exr_image_free(&img);
    exr_image_free(&back);
}

int main(void)
{
    RUN(half_round_equals_read_back);
    RUN(image_helpers);
    RUN(round_trip_values);
    RUN(half_rounding_matches_reference);
    RUN(attributes_round_trip);
    RUN(compressions_round_trip);
    RUN(odd_sizes);
    RUN(atomic_missing_directory);
    RUN(atomic_no_temp_left_after_success);
    RUN(atomic_failure_midway);
    RUN(atomic_failure_at_header);
    RUN(read_refuses_fifo_and_directory);
    RUN(bad_images_refused);
    RUN(writer_thread_writes_all_frames_1_thread);
    RUN(writer_thread_writes_all_frames_4_threads);
    RUN(writer_thread_error_is_sticky_1_thread);
    RUN(writer_thread_error_is_sticky_4_threads);
    RUN(writer_desc_defaults);
    RUN(writer_threads_many_frames);
    RUN(writer_threads_error_with_others_succeeding);
    RUN(writer_threads_same_path_in_order);
    RUN(read_missing_or_damaged_files);
    RUN(multipart_image_chain);
    RUN(multipart_round_trip);
    RUN(multipart_many_channels_three_parts);
    RUN(multipart_sizes_independent);
    RUN(multipart_bad_chains_refused);
    RUN(multipart_truncated_fails);
    RUN(multipart_writer_thread);
    return test_summary();
}
