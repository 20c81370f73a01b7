/* Shader assembly: #include expansion from the embedded tree, defines, #line mapping of driver logs. */
#include <string.h>

#include "core/embedded.h"
#include "core/log.h"
#include "gl/shader_src.h"
#include "test.h"

TEST(forward_frag_expands_includes)
{
    const char *defs[] = {"ALPHA_MODE 1", "PASS_MASK 1"};
    shader_src s;
    CHECK(shader_src_build("shaders/forward.frag", defs, 2, &s) == FS_OK);
    CHECK(strncmp(s.text, "#version 450 core\n#define ALPHA_MODE 1\n#define PASS_MASK 1\n", 58) == 0);
    CHECK(strstr(s.text, "\n#include") == NULL);           /* every include directive replaced */
    CHECK(strstr(s.text, "bool alpha_test(") != NULL);      /* alpha_test.glsl is in */
    CHECK(strstr(s.text, "float alpha_hashed_threshold(") != NULL); /* and alpha_hash.glsl, nested */
    CHECK(strstr(s.text, "vec3 shade_lambert") != NULL);
    CHECK(s.file_count >= 3);
    CHECK(strcmp(s.files[0], "shaders/forward.frag") == 0);
    shader_src_free(&s);
    CHECK(s.text == NULL);
}

TEST(driver_logs_map_to_files)
{
    shader_src s;
    CHECK(shader_src_build("shaders/forward.frag", (const char *[]){"PASS_OPAQUE 1"}, 1, &s) == FS_OK);
    int inc = -1;
    for (int i = 0; i < s.file_count; i++)
        if (strcmp(s.files[i], "shaders/common/lighting.glsl") == 0)
            inc = i;
    CHECK(inc > 0);
    char log[256], out[512];
    snprintf(log, sizeof log, "%d:7(12): error: `foo' undeclared\n0:3(1): warning: x", inc);
    shader_src_translate_log(&s, log, out, sizeof out);
    CHECK(strstr(out, "shaders/common/lighting.glsl:7: error: `foo' undeclared") != NULL);
    CHECK(strstr(out, "shaders/forward.frag:3: warning: x") != NULL);
    snprintf(log, sizeof log, "%d(9) : error C1008: undefined variable", inc); /* NVIDIA style */
    shader_src_translate_log(&s, log, out, sizeof out);
    CHECK(strcmp(out, "shaders/common/lighting.glsl:9: error C1008: undefined variable") == 0);
    shader_src_translate_log(&s, "no location here", out, sizeof out);
    CHECK(strcmp(out, "no location here") == 0);
    /* A tiny output buffer truncates without overflowing. */
    char tiny[8];
    shader_src_translate_log(&s, log, tiny, sizeof tiny);
    CHECK(strlen(tiny) < sizeof tiny);
    shader_src_free(&s);
}

TEST(line_directives_follow_the_included_file)
{
    /* After an include, numbering resumes at the line after the #include in the parent. */
    shader_src s;
    CHECK(shader_src_build("shaders/forward.frag", (const char *[]){"PASS_OPAQUE 1"}, 1, &s) == FS_OK);
    const embedded_file *f = embedded_find("shaders/forward.frag");
    CHECK(f != NULL);
    int line = 1, include_line = -1;
    for (const char *p = f->data; *p; p++) {
        if (!strncmp(p, "#include \"common/lighting.glsl\"", 31))
            include_line = line;
        if (*p == '\n')
            line++;
    }
    CHECK(include_line > 0);
    char expect[64];
    snprintf(expect, sizeof expect, "#line %d 0\n", include_line + 1);
    CHECK(strstr(s.text, expect) != NULL);
    shader_src_free(&s);
}

TEST(missing_files_are_errors)
{
    log_set_quiet_errors(true);
    shader_src s;
    CHECK(shader_src_build("shaders/nope.frag", NULL, 0, &s) == FS_ERR_SHADER);
    CHECK(s.text == NULL);
    log_set_quiet_errors(false);
}

TEST(every_embedded_shader_assembles)
{
    int n = 0;
    for (int i = 0; i < embedded_file_count; i++) {
        if (strncmp(embedded_files[i].path, "shaders/", 8) != 0)
            continue;
        shader_src s;
        CHECK(shader_src_build(embedded_files[i].path, NULL, 0, &s) == FS_OK);
        shader_src_free(&s);
        n++;
    }
    CHECK(n >= 4);
}

int main(void)
{
    RUN(forward_frag_expands_includes);
    RUN(driver_logs_map_to_files);
    RUN(line_directives_follow_the_included_file);
    RUN(missing_files_are_errors);
    RUN(every_embedded_shader_assembles);
    return test_summary();
}
