/* test_exr_views.c: two eyes in one EXR by OpenEXR's multi-view convention (src/output/
 * exr_views.c): stringvector attributes, the channel naming rule, joining two single-view images
 * and reading each view back exactly (at half precision) through fovsim's reader. External
 * readers (oiiotool, exrmultiview) are in test_exr_views_tools.c. */
#include <stdbool.h>

#include "core/log.h"
#include "output/exr_write.h"
#include "test.h"

#include "exr_eyes.h"

// >>tests

TEST(string_vector_attribute)
{
    exr_image img;
    CHECK(exr_image_init(&img, 2, 2));
    CHECK(exr_image_add_channel(&img, "R") != NULL);
    const char *v[] = {"left", "", "a longer string with spaces"};
    CHECK(exr_image_set_string_vector(&img, "fovsim:list", v, 3));
    const exr_attr *a = exr_image_attr(&img, "fovsim:list");
    CHECK(a && a->type == FS_EXR_ATTR_STRING_VECTOR && a->i == 3);
    CHECK(a && strcmp(exr_attr_string_at(a, 0), "left") == 0);
    CHECK(a && strcmp(exr_attr_string_at(a, 1), "") == 0);
    CHECK(a && strcmp(exr_attr_string_at(a, 2), v[2]) == 0);
    CHECK(a && exr_attr_string_at(a, 3) == NULL && exr_attr_string_at(a, -1) == NULL);
    /* Too long or too many: refused whole, the old value kept (nothing is truncated). */
    char big[600];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    const char *toolong[] = {big};
    const char *many[EXR_MAX_VECTOR_STRINGS + 1];
    for (int k = 0; k <= EXR_MAX_VECTOR_STRINGS; k++)
        many[k] = "v";
    log_set_quiet_errors(true);
    CHECK(!exr_image_set_string_vector(&img, "fovsim:list", toolong, 1));
    CHECK(!exr_image_set_string_vector(&img, "fovsim:list", many, EXR_MAX_VECTOR_STRINGS + 1));
    log_set_quiet_errors(false);
    a = exr_image_attr(&img, "fovsim:list");
    CHECK(a && a->i == 3);
    CHECK(exr_image_set_string_vector(&img, "fovsim:empty", NULL, 0));

    const char *path = path_of("views_stringvector.exr");
    CHECK(exr_write_file(path, &img, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&img);
    exr_image back;
    CHECK(exr_read_file(path, &back) == FS_OK);
    a = exr_image_attr(&back, "fovsim:list");
    CHECK(a && a->type == FS_EXR_ATTR_STRING_VECTOR && a->i == 3);
    for (int k = 0; a && k < 3; k++)
        CHECK(exr_attr_string_at(a, k) && strcmp(exr_attr_string_at(a, k), v[k]) == 0);
    a = exr_image_attr(&back, "fovsim:empty");
    CHECK(a && a->type == FS_EXR_ATTR_STRING_VECTOR && a->i == 0);
    CHECK(exr_image_view_count(&back) == 0); /* no multiView */
    exr_image_free(&back);
}

TEST(view_names_checked)
{
    exr_image img;
    CHECK(exr_image_init(&img, 2, 2));
    const char *ok[] = {"left", "right"};
    const char *dot[] = {"left", "ri.ght"};
    const char *space[] = {"left eye"};
    const char *twice[] = {"left", "left"};
    const char *empty[] = {""};
    log_set_quiet_errors(true);
    CHECK(!exr_image_set_views(&img, dot, 2));
    CHECK(!exr_image_set_views(&img, space, 1));
    CHECK(!exr_image_set_views(&img, twice, 2));
    CHECK(!exr_image_set_views(&img, empty, 1));
    CHECK(!exr_image_set_views(&img, ok, 0));
    log_set_quiet_errors(false);
    CHECK(exr_image_view_count(&img) == 0 && exr_image_attr(&img, "multiView") == NULL);
    CHECK(exr_image_set_views(&img, ok, 2));
    CHECK(exr_image_view_count(&img) == 2);
    CHECK(strcmp(exr_image_view_name(&img, 0), "left") == 0);
    CHECK(strcmp(exr_image_view_name(&img, 1), "right") == 0);
    CHECK(exr_image_view_name(&img, 2) == NULL);
    exr_image_free(&img);
}

/* The naming rule against the examples of OpenEXR's ImfMultiView.h and MultiViewOpenEXR. */
TEST(channel_naming_rule)
{
    char out[64];
    CHECK(exr_view_channel_name("R", "left", true, out, sizeof out) && strcmp(out, "R") == 0);
    CHECK(exr_view_channel_name("R", "right", false, out, sizeof out) && strcmp(out, "right.R") == 0);
    CHECK(exr_view_channel_name("coverage", "right", false, out, sizeof out) &&
          strcmp(out, "right.coverage") == 0);
    CHECK(exr_view_channel_name("hashed.R", "left", true, out, sizeof out) &&
          strcmp(out, "hashed.left.R") == 0);
    CHECK(exr_view_channel_name("noshadows.nearscene.G", "right", false, out, sizeof out) &&
          strcmp(out, "noshadows.nearscene.right.G") == 0);
    CHECK(!exr_view_channel_name("coverage", "right", false, out, 10)); /* does not fit */

    exr_image img;
    CHECK(exr_image_init(&img, 1, 1));
    char base[64];
    CHECK(exr_channel_view(&img, "R", base, sizeof base) == -1); /* no multiView: no view */
    const char *views[] = {"left", "right"};
    CHECK(exr_image_set_views(&img, views, 2));
    static const struct { const char *name; int view; const char *base; } cases[] = {
        {"R", 0, "R"},
        {"left.Z", 0, "Z"},
        {"diffuse.left.R", 0, "diffuse.R"},
        {"right.R", 1, "R"},
        {"right.Z", 1, "Z"},
        {"diffuse.right.R", 1, "diffuse.R"},
        {"tmp.R", -1, NULL},
        {"right.diffuse.R", -1, NULL},
        {"diffuse.tmp.R", -1, NULL},
        {"a.b.right.c", 1, "a.b.c"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int v = exr_channel_view(&img, cases[k].name, base, sizeof base);
        if (v != cases[k].view || (v >= 0 && strcmp(base, cases[k].base) != 0)) {
            fprintf(stderr, "  %s: view %d base '%s'\n", cases[k].name, v, v >= 0 ? base : "");
            CHECK(false);
        }
    }
    exr_image_free(&img);
}

/* Two eyes joined, written, read back by fovsim's reader, each view extracted: the same channels,
 * values at half precision and attributes as each eye had. */
TEST(two_eyes_round_trip)
{
    exr_image left, right, both;
    make_eye(&left, 0, -0.125f);
    make_eye(&right, 1, 0.125f);
    CHECK(exr_image_join_eyes(&both, &left, &right) == FS_OK);
    CHECK(both.channel_count == 2 * NEYE);
    const char *path = path_of("views_two_eyes.exr");
    CHECK(exr_write_file(path, &both, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&both);

    exr_image file;
    CHECK(exr_read_file(path, &file) == FS_OK);
    CHECK(exr_image_view_count(&file) == 2);
    CHECK(exr_image_view_name(&file, 0) && strcmp(exr_image_view_name(&file, 0), "left") == 0);
    CHECK(exr_image_view_name(&file, 1) && strcmp(exr_image_view_name(&file, 1), "right") == 0);
    /* The names in the file, by the rule: the left (default) eye's plain channels unprefixed. */
    static const char *const stored[] = {"R", "A", "coverage", "hashed.left.R", "ring.left.id",
                                         "right.R", "right.A", "right.coverage",
                                         "hashed.right.R", "ring.right.id"};
    for (size_t k = 0; k < sizeof stored / sizeof stored[0]; k++)
        CHECK(exr_image_channel(&file, stored[k]) != NULL);
    CHECK(exr_image_channel(&file, "left.R") == NULL && exr_image_channel(&file, "hashed.R") == NULL);
    /* Attributes: shared once; the right eye's own under "right.". */
    const exr_attr *a = exr_image_attr(&file, "fovsim:gaze");
    CHECK(a && a->f[0] == -0.125f);
    a = exr_image_attr(&file, "right.fovsim:gaze");
    CHECK(a && a->type == FS_EXR_ATTR_V2F && a->f[0] == 0.125f && a->f[1] == 0.25f);
    CHECK(exr_image_attr(&file, "right.fovsim:frame") == NULL);
    CHECK(exr_image_attr(&file, "right.fovsim:ipd_half_m") != NULL);

    exr_image views[2];
    const exr_image *eyes[2] = {&left, &right};
    for (int e = 0; e < 2; e++) {
        CHECK(exr_image_extract_view(&file, e == 0 ? "left" : "right", &views[e]) == FS_OK);
        CHECK(is_eye(&views[e], e));
        CHECK(exr_image_view_count(&views[e]) == 0);
        /* Every attribute of the eye, with its value; nothing of the other eye's own. */
        CHECK(views[e].attr_count == eyes[e]->attr_count);
        for (int k = 0; k < eyes[e]->attr_count; k++) {
            const exr_attr *want = &eyes[e]->attrs[k];
            const exr_attr *got = exr_image_attr(&views[e], want->name);
            CHECK(got && got->type == want->type && got->i == want->i &&
                  strcmp(got->s, want->s) == 0 && got->f[0] == want->f[0] && got->f[1] == want->f[1]);
        }
        exr_image_free(&views[e]);
    }
    log_set_quiet_errors(true);
    CHECK(exr_image_extract_view(&file, "centre", &views[0]) == FS_ERR_IO);
    log_set_quiet_errors(false);
    CHECK(views[0].channel_count == 0);
    exr_image_free(&file);
    exr_image_free(&left);
    exr_image_free(&right);
}

/* A view-unaware reader sees the left eye: R, G, B, A of the file are the left eye's. */
TEST(default_view_is_left)
{
    exr_image left, right, both;
    make_eye(&left, 0, 0.0f);
    make_eye(&right, 1, 0.0f);
    CHECK(exr_image_join_eyes(&both, &left, &right) == FS_OK);
    const float *r = exr_image_channel(&both, "R");
    const float *rr = exr_image_channel(&both, "right.R");
    CHECK(r && rr && r[5] == eye_value(0, 0, 5) && rr[5] == eye_value(1, 0, 5));
    exr_image_free(&both);
    exr_image_free(&left);
    exr_image_free(&right);
}

TEST(bad_joins_refused)
{
    exr_image left, right, out;
    make_eye(&left, 0, 0.0f);
    make_eye(&right, 1, 0.0f);
    log_set_quiet_errors(true);

    exr_image small;
    CHECK(exr_image_init(&small, W - 1, H));
    CHECK(exr_image_add_channel(&small, "R") != NULL);
    CHECK(exr_image_join_eyes(&out, &left, &small) == FS_ERR_INTERNAL); /* sizes differ */
    CHECK(out.channel_count == 0 && out.planes[0] == NULL);
    exr_image_free(&small);

    const exr_image *same[2] = {&left, &right};
    const char *dup[2] = {"left", "left"};
    CHECK(exr_image_join_views(&out, same, dup, 2) == FS_ERR_INTERNAL);
    const char *dotted[2] = {"left", "right.eye"};
    CHECK(exr_image_join_views(&out, same, dotted, 2) == FS_ERR_INTERNAL);

    /* A channel already carrying a view where the rule puts one would read as another's. */
    CHECK(exr_image_add_channel(&right, "layer.left.R") != NULL);
    CHECK(exr_image_join_eyes(&out, &left, &right) == FS_ERR_INTERNAL);
    exr_image_free(&right);
    make_eye(&right, 1, 0.0f);
    exr_image_set_int(&right, "left.fovsim:frame", 1);
    CHECK(exr_image_join_eyes(&out, &left, &right) == FS_ERR_INTERNAL);
    exr_image_free(&right);

    /* An image that is already multi-view, or a chain of parts. */
    make_eye(&right, 1, 0.0f);
    const char *lr[2] = {"left", "right"};
    CHECK(exr_image_set_views(&right, lr, 2));
    CHECK(exr_image_join_eyes(&out, &left, &right) == FS_ERR_INTERNAL);
    exr_image_free(&right);
    make_eye(&right, 1, 0.0f);
    exr_image part;
    make_eye(&part, 1, 0.0f);
    CHECK(exr_image_set_part_name(&right, "a") && exr_image_set_part_name(&part, "b"));
    CHECK(exr_image_append_part(&right, &part));
    CHECK(exr_image_join_eyes(&out, &left, &right) == FS_ERR_INTERNAL);
    exr_image_free(&right);

    /* More channels in all than EXR_MAX_CHANNELS. */
    exr_image wide[2];
    for (int e = 0; e < 2; e++) {
        CHECK(exr_image_init(&wide[e], 2, 2));
        for (int c = 0; c < EXR_MAX_CHANNELS / 2 + 1; c++) {
            char name[16];
            snprintf(name, sizeof name, "c%d", c);
            CHECK(exr_image_add_channel(&wide[e], name) != NULL);
        }
    }
    CHECK(exr_image_join_eyes(&out, &wide[0], &wide[1]) == FS_ERR_INTERNAL);
    CHECK(out.channel_count == 0);
    exr_image_free(&wide[0]);
    exr_image_free(&wide[1]);
    log_set_quiet_errors(false);

    /* The good pair still joins: the refusals above changed neither input. */
    make_eye(&right, 1, 0.0f);
    CHECK(exr_image_join_eyes(&out, &left, &right) == FS_OK);
    exr_image_free(&out);
    exr_image_free(&left);
    exr_image_free(&right);
}

/* One view only is a valid multi-view file too: its channels keep their names. */
TEST(single_view_join)
{
    exr_image left, out;
    make_eye(&left, 0, 0.0f);
    const exr_image *one[1] = {&left};
    const char *name[1] = {"left"};
    CHECK(exr_image_join_views(&out, one, name, 1) == FS_OK);
    CHECK(exr_image_channel(&out, "R") && exr_image_channel(&out, "hashed.left.R"));
    exr_image back;
    CHECK(exr_image_extract_view(&out, "left", &back) == FS_OK);
    CHECK(back.channel_count == NEYE && exr_image_channel(&back, "hashed.R"));
    exr_image_free(&back);
    exr_image_free(&out);
    exr_image_free(&left);
}

/* The moving join gives the copying join's image and leaves the eyes empty; when refused, it
 * leaves them as they were. */
TEST(move_join_equals_copy_join)
{
    exr_image left, right, copied, moved;
    make_eye(&left, 0, -0.5f);
    make_eye(&right, 1, 0.5f);
    CHECK(exr_image_join_eyes(&copied, &left, &right) == FS_OK);
    const float *left_r = exr_image_channel(&left, "R");
    CHECK(exr_image_join_eyes_move(&moved, &left, &right) == FS_OK);
    CHECK(exr_image_channel(&moved, "R") == left_r); /* moved, not copied */
    CHECK(left.channel_count == 0 && right.channel_count == 0 && left.planes[0] == NULL);
    CHECK(moved.channel_count == copied.channel_count && moved.attr_count == copied.attr_count);
    for (int c = 0; c < copied.channel_count; c++) {
        const float *m = exr_image_channel(&moved, copied.channel_names[c]);
        CHECK(m && memcmp(m, copied.planes[c], sizeof(float) * W * H) == 0);
    }
    for (int a = 0; a < copied.attr_count; a++)
        CHECK(memcmp(&copied.attrs[a], &moved.attrs[a], sizeof copied.attrs[a]) == 0);
    exr_image_free(&moved);
    exr_image_free(&copied);

    exr_image small;
    make_eye(&left, 0, 0.0f);
    CHECK(exr_image_init(&small, W + 1, H));
    CHECK(exr_image_add_channel(&small, "R") != NULL);
    log_set_quiet_errors(true);
    CHECK(exr_image_join_eyes_move(&moved, &left, &small) == FS_ERR_INTERNAL);
    log_set_quiet_errors(false);
    CHECK(left.channel_count == NEYE && exr_image_channel(&left, "coverage") &&
          exr_image_channel(&left, "coverage")[5] == eye_value(0, 4, 5));
    CHECK(small.channel_count == 1 && moved.channel_count == 0);
    exr_image_free(&small);
    exr_image_free(&left);
}

/* Two eyes as one part of a multi-part file (a comparison frame's layers beside its grid): the
 * part keeps its multiView and each eye reads back from it. */
TEST(two_eyes_in_a_part)
{
    exr_image grid, left, right, layers;
    CHECK(exr_image_init(&grid, 2 * W, H));
    CHECK(exr_image_add_channel(&grid, "R") != NULL);
    CHECK(exr_image_set_part_name(&grid, "compare"));
    make_eye(&left, 0, 0.0f);
    make_eye(&right, 1, 0.0f);
    CHECK(exr_image_join_eyes(&layers, &left, &right) == FS_OK);
    CHECK(exr_image_set_part_name(&layers, "layers"));
    CHECK(exr_image_append_part(&grid, &layers));
    const char *path = path_of("views_in_part.exr");
    CHECK(exr_write_file(path, &grid, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&grid);
    exr_image part0, part1, eye;
    CHECK(exr_read_part(path, 0, &part0) == FS_OK);
    CHECK(exr_image_view_count(&part0) == 0);
    CHECK(exr_read_part(path, 1, &part1) == FS_OK);
    CHECK(exr_image_view_count(&part1) == 2);
    for (int e = 0; e < 2; e++) {
        CHECK(exr_image_extract_view(&part1, e ? "right" : "left", &eye) == FS_OK);
        CHECK(is_eye(&eye, e));
        exr_image_free(&eye);
    }
    exr_image_free(&part0);
    exr_image_free(&part1);
    exr_image_free(&left);
    exr_image_free(&right);
}

int main(void)
{
    RUN(string_vector_attribute);
    RUN(view_names_checked);
    RUN(channel_naming_rule);
    RUN(two_eyes_round_trip);
    RUN(default_view_is_left);
    RUN(bad_joins_refused);
    RUN(single_view_join);
    RUN(move_join_equals_copy_join);
    RUN(two_eyes_in_a_part);
    return test_summary();
}
