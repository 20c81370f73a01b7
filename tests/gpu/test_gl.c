/* GL plumbing: shader errors point at file:line, the GLSL alpha test agrees with its C twin,
 * a rendered frame survives the EXR round trip with its attributes. */
#include <unistd.h>

#include "gl/gl_program.h"
#include "gpu_util.h"
#include "passes/alpha_test.h"

/* Runs fn with stderr captured into buf. */
static void capture_stderr(void (*fn)(void *), void *arg, char *buf, size_t n)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/stderr.txt", test_out_dir());
    fflush(stderr);
    int saved = dup(2);
    FILE *f = fopen(path, "w+");
    dup2(fileno(f), 2);
    fn(arg);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    rewind(f);
    size_t k = fread(buf, 1, n - 1, f);
    buf[k] = '\0';
    fclose(f);
}

static void build_without_pass_define(void *st)
{
    gpu_program_handle h;
    *(fs_status *)st = gl_program_build(
        &(gl_program_desc){.vs = "shaders/forward.vert", .fs = "shaders/forward.frag", .label = "test"}, &h);
}

TEST(shader_errors_name_file_and_line)
{
    fs_status st = FS_OK;
    char log[8192];
    capture_stderr(build_without_pass_define, &st, log, sizeof log);
    CHECK(st == FS_ERR_SHADER);
    /* forward.frag has `#error` for a missing PASS_* define: the message must name that file and a line. */
    CHECK(strstr(log, "shaders/forward.frag:") != NULL);
    CHECK(strstr(log, "PASS_OPAQUE") != NULL);
    fprintf(stderr, "%s", log);
}

/* One camera-facing quad, 1 texel per pixel, alpha ramp 0..255 over 256 texels, nearest filtering:
 * pixel x sees alpha x/255 at mip 0, so coverage(x) must equal the C twin's verdict. */
TEST(glsl_traditional_test_agrees_with_the_c_twin)
{
    enum { W = 256, H = 16 };
    scene sc;
    scene_init_defaults(&sc);
    image_rgba8 img = {.width = W, .height = 1, .rgba = malloc(W * 4)};
    for (int x = 0; x < W; x++) {
        img.rgba[4 * x] = 200;
        img.rgba[4 * x + 1] = 100;
        img.rgba[4 * x + 2] = 50;
        img.rgba[4 * x + 3] = (uint8_t)x;
    }
    material m = {.base_color = {1, 1, 1, 1}, .base_color_image = 0, .alpha_kind = ALPHA_KIND_MASK,
                  .alpha_cutoff = 0.5f, .double_sided = true, .mag_filter = TEX_FILTER_NEAREST,
                  .wrap_s = TEX_WRAP_CLAMP, .wrap_t = TEX_WRAP_CLAMP};
    /* Quad covering exactly the view of an orthographic-like setup: the camera at distance d with
     * hfov 90 sees x in [-d, d]; the quad spans it exactly. */
    float d = 1.0f, hy = d * (float)H / (float)W;
    float pos[12] = {-d, -hy, 0, d, -hy, 0, d, hy, 0, -d, hy, 0};
    float uv[8] = {0, 0.5f, 1, 0.5f, 1, 0.5f, 0, 0.5f};
    asset a = quad_asset("ramp", pos, uv, m, &img);
    CHECK(scene_add_asset(&sc, &a) == 0);
    CHECK(scene_add_instance(&sc, 0, m4_identity()));
    sc.camera.count = 1;
    sc.camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, d), .target = v3(0, 0, 0), .hfov_deg = 90};
    sc.display.hfov_deg = 90;

    float cutoffs[] = {0.5f, 0.2f, 0.0f, 1.0f, 0.73f};
    for (int c = 0; c < 5; c++) {
        sc.assets[0].materials[0].alpha_cutoff = cutoffs[c];
        exr_image out;
        CHECK(gpu_render(&sc, ALPHA_MODE_TRADITIONAL, W, H, 0.0f, &out) == FS_OK);
        const float *cov = exr_image_channel(&out, "coverage");
        int mismatches = 0;
        for (int x = 0; x < W; x++) {
            /* The texture stores alpha as half; the twin sees the same rounding. */
            float alpha = (float)x / 255.0f;
            bool pass = alpha_test_traditional(alpha, cutoffs[c]);
            float got = cov[(H / 2) * W + x];
            if ((got == 1.0f) != pass) {
                if (mismatches++ < 3)
                    fprintf(stderr, "cutoff %.2f x %d alpha %.4f: GPU %.1f, C %d\n", cutoffs[c], x, alpha, got, pass);
            }
        }
        fprintf(stderr, "cutoff %.2f: %d mismatches of %d\n", cutoffs[c], mismatches, W);
        CHECK(mismatches == 0);
        exr_image_free(&out);
    }
    scene_free(&sc);
}

TEST(rendered_frame_round_trips_through_exr)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    exr_image img, back;
    CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, 120, 68, 2.0f, &img) == FS_OK);
    exr_image_set_string(&img, "fovsim:renderer", gl_device_renderer());
    exr_image_set_int(&img, "fovsim:frame", 48);
    exr_image_set_v2f(&img, "fovsim:gaze", 0.25f, 0.75f);
    char path[1200];
    snprintf(path, sizeof path, "%s/roundtrip.exr", test_out_dir());
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_OK);
    CHECK(exr_read_file(path, &back) == FS_OK);
    CHECK(back.width == 120 && back.height == 68 && back.channel_count == 5);
    double max_rel = 0;
    for (int c = 0; c < img.channel_count; c++) {
        const float *b = exr_image_channel(&back, img.channel_names[c]);
        CHECK(b != NULL);
        for (int i = 0; b && i < 120 * 68; i++) {
            double e = fabs(b[i] - img.planes[c][i]) / fmax(fabs(img.planes[c][i]), 6.1e-5);
            max_rel = fmax(max_rel, e);
        }
    }
    fprintf(stderr, "max relative error after half storage: %.2e\n", max_rel);
    CHECK(max_rel <= 1.0 / 2048.0); /* half has 11 significant bits: round to nearest */
    const exr_attr *a = exr_image_attr(&back, "fovsim:renderer");
    CHECK(a && a->type == FS_EXR_ATTR_STRING && strcmp(a->s, gl_device_renderer()) == 0);
    a = exr_image_attr(&back, "fovsim:frame");
    CHECK(a && a->type == FS_EXR_ATTR_INT && a->i == 48);
    a = exr_image_attr(&back, "fovsim:gaze");
    CHECK(a && a->type == FS_EXR_ATTR_V2F && a->f[0] == 0.25f && a->f[1] == 0.75f);
    exr_image_free(&img);
    exr_image_free(&back);
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(shader_errors_name_file_and_line);
    RUN(glsl_traditional_test_agrees_with_the_c_twin);
    RUN(rendered_frame_round_trips_through_exr);
    gl_device_destroy();
    return test_summary();
}
