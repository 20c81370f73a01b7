/* The one-definition tables: the alpha modes (FS_ALPHA_MODES, common/shared_defs.h) and the columns
 * of metrics.csv (METRICS_CSV_COLUMNS, metrics/metrics.h). Each row is checked through what reads
 * it, so a new row is tested here without a new test. */
#include <string.h>

#include "commands/check.h"
#include "gl/shader_src.h"
#include "metrics/metrics.h"
#include "scene/scene.h"
#include "test.h"

TEST(every_mode_round_trips_its_name)
{
    CHECK(strcmp(alpha_mode_name(ALPHA_MODE_DEFAULT), "default") == 0);
    CHECK(alpha_mode_name(ALPHA_MODE_COUNT) == NULL);
    CHECK(alpha_mode_parse("default") == ALPHA_MODE_DEFAULT); /* "not set" is not a mode to ask for */
    CHECK(alpha_mode_parse("nope") == ALPHA_MODE_DEFAULT && alpha_mode_parse(NULL) == ALPHA_MODE_DEFAULT);
    /* The list names every mode once, in the table's order, ", " between them. */
    char list[512] = "";
    for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++) {
        const char *name = alpha_mode_name((alpha_mode)m);
        CHECK(name != NULL && name[0]);
        CHECK(alpha_mode_parse(name) == (alpha_mode)m);
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", m > ALPHA_MODE_TRADITIONAL ? ", " : "", name);
    }
    CHECK(strcmp(alpha_mode_list(), list) == 0);
    CHECK(strcmp(alpha_mode_list(), "traditional, stochastic, hashed, a2c, hashed_a2c, castano, mipscale") == 0);
}

TEST(every_mode_has_its_own_colour)
{
    char a[8], b[8];
    for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++) {
        alpha_mode_colour((alpha_mode)m, a);
        CHECK(strlen(a) == 7 && a[0] == '#' && strspn(a + 1, "0123456789abcdef") == 6);
        for (int k = ALPHA_MODE_TRADITIONAL; k < m; k++)
            CHECK(strcmp(alpha_mode_colour((alpha_mode)k, b), a) != 0);
    }
    CHECK(strcmp(alpha_mode_colour(ALPHA_MODE_TRADITIONAL, a), "#1f77b4") == 0);
    CHECK(strcmp(alpha_mode_colour(ALPHA_MODE_COUNT, a), "#000000") == 0);
}

TEST(traits_are_the_rows)
{
    CHECK(alpha_mode_traits(ALPHA_MODE_DEFAULT) == 0 && alpha_mode_traits(ALPHA_MODE_COUNT) == 0);
    CHECK(alpha_mode_has(ALPHA_MODE_A2C, ALPHA_TRAIT_MSAA | ALPHA_TRAIT_GL_A2C));
    CHECK(alpha_mode_has(ALPHA_MODE_HASHED_A2C, ALPHA_TRAIT_MSAA | ALPHA_TRAIT_HASH | ALPHA_TRAIT_NOISE));
    CHECK(!alpha_mode_has(ALPHA_MODE_HASHED_A2C, ALPHA_TRAIT_GL_A2C));
    CHECK(alpha_mode_has(ALPHA_MODE_CASTANO, ALPHA_TRAIT_COVERAGE_MIPS));
    CHECK(alpha_mode_has(ALPHA_MODE_STOCHASTIC, ALPHA_TRAIT_NOISE) && !alpha_mode_has(ALPHA_MODE_STOCHASTIC, ALPHA_TRAIT_HASH));
    CHECK(alpha_mode_traits(ALPHA_MODE_TRADITIONAL) == 0 && alpha_mode_traits(ALPHA_MODE_MIPSCALE) == 0);
}

TEST(every_shader_sees_every_mode_id)
{
    shader_src s;
    CHECK(shader_src_build("shaders/fullscreen.vert", NULL, 0, &s) == FS_OK);
    for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++) {
        char upper[64], line[96];
        const char *n = alpha_mode_name((alpha_mode)m);
        size_t i = 0;
        for (; n[i] && i + 1 < sizeof upper; i++)
            upper[i] = (char)(n[i] >= 'a' && n[i] <= 'z' ? n[i] - 'a' + 'A' : n[i]);
        upper[i] = '\0';
        snprintf(line, sizeof line, "\n#define ALPHA_MODE_ID_%s %d\n", upper, m);
        CHECK(strstr(s.text, line) != NULL);
    }
    shader_src_free(&s);
}

TEST(metrics_columns_are_the_header)
{
    char header[512] = "";
    for (int c = 0; c < METRICS_COL_COUNT; c++) {
        const char *name = metrics_column_name((metrics_column)c);
        CHECK(metrics_column_of(name) == (metrics_column)c);
        snprintf(header + strlen(header), sizeof header - strlen(header), "%s%s", c ? "," : "", name);
    }
    CHECK(strcmp(header, "frame,time,mode,ring,pixels,coverage,ref_coverage,coverage_ratio,rmse,alpha_rmse,flip,psnr,"
                         "temporal_error,disoccluded,static_flicker,gaze_event,frame_ms") == 0);
    CHECK(metrics_column_of("nope") == METRICS_COL_COUNT);
    CHECK(strcmp(metrics_column_name(METRICS_COL_COUNT), "") == 0 && metrics_column_flags(METRICS_COL_COUNT) == 0);
}

TEST(check_judges_the_columns_that_say_how)
{
    /* fovsim check's metrics of metrics.csv are the columns of their names, each judged one way. */
    for (int m = 0; m < CHECK_PIXEL; m++) {
        metrics_column c = metrics_column_of(check_metric_name((check_metric)m));
        CHECK(c < METRICS_COL_COUNT);
        unsigned f = metrics_column_flags(c);
        CHECK(((f & METRICS_COLF_GROWTH) != 0) + ((f & METRICS_COLF_EITHER_WAY) != 0) == 1);
    }
    /* and no other column claims a way to be judged */
    int judged = 0;
    for (int c = 0; c < METRICS_COL_COUNT; c++)
        judged += (metrics_column_flags((metrics_column)c) & (METRICS_COLF_GROWTH | METRICS_COLF_EITHER_WAY)) != 0;
    CHECK(judged == CHECK_PIXEL);
}

int main(void)
{
    RUN(every_mode_round_trips_its_name);
    RUN(every_mode_has_its_own_colour);
    RUN(traits_are_the_rows);
    RUN(every_shader_sees_every_mode_id);
    RUN(metrics_columns_are_the_header);
    RUN(check_judges_the_columns_that_say_how);
    return test_summary();
}
