/* The logger's escaping (issue 17 defect 5): input quoted in a message can neither break the line
 * nor reach the terminal as a control sequence; printable ASCII and well-formed UTF-8 pass. */
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "test.h"

/* log_escape_write of `in` (n bytes) into a NUL-terminated string in `out`. */
static void esc(const char *in, size_t n, char *out, size_t cap)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    CHECK(f != NULL);
    if (!f)
        return;
    log_escape_write(f, in, n);
    fclose(f);
    snprintf(out, cap, "%s", buf ? buf : "");
    free(buf);
}

#define ESC_EQ(in, want)                                                                    \
    do {                                                                                    \
        char got_[256];                                                                     \
        esc((in), sizeof(in) - 1, got_, sizeof got_);                                       \
        CHECK(strcmp(got_, (want)) == 0);                                                   \
        if (strcmp(got_, (want)) != 0)                                                      \
            fprintf(stderr, "  escaped to '%s', wanted '%s'\n", got_, (want));              \
    } while (0)

TEST(printable_text_passes)
{
    ESC_EQ("scenes/a b.json: instances[0].scale: expected a number, got 'big'",
           "scenes/a b.json: instances[0].scale: expected a number, got 'big'");
    ESC_EQ("Fo\xc3\xa4rn \xe2\x80\x94 \xf0\x9f\x8c\xbf.gltf", "Fo\xc3\xa4rn \xe2\x80\x94 \xf0\x9f\x8c\xbf.gltf");
    ESC_EQ("back\\slash", "back\\slash");
}

TEST(control_characters_are_escaped)
{
    ESC_EQ("a\nfovsim: error: forged", "a\\nfovsim: error: forged");
    ESC_EQ("\x1b[31mred\x1b[0m", "\\x1b[31mred\\x1b[0m");
    ESC_EQ("cr\rtab\tdel\x7f bell\x07", "cr\\rtab\\tdel\\x7f bell\\x07");
    char nul[] = {'a', 0, 'b'};
    char got[64];
    esc(nul, sizeof nul, got, sizeof got);
    CHECK(strcmp(got, "a\\x00b") == 0);
}

TEST(malformed_utf8_and_c1_controls_are_escaped)
{
    ESC_EQ("\xc2\x9b" "31m", "\\xc2\\x9b31m");  /* U+009B CSI, a C1 control */
    ESC_EQ("\x9b" "2J", "\\x9b2J");              /* a bare 8-bit CSI */
    ESC_EQ("\xc0\xaf", "\\xc0\\xaf");            /* overlong '/' */
    ESC_EQ("\xed\xa0\x80", "\\xed\\xa0\\x80");   /* a surrogate */
    ESC_EQ("\xe2\x80", "\\xe2\\x80");            /* truncated */
    ESC_EQ("\xf5\x80\x80\x80", "\\xf5\\x80\\x80\\x80");
}

int main(void)
{
    RUN(printable_text_passes);
    RUN(control_characters_are_escaped);
    RUN(malformed_utf8_and_c1_controls_are_escaped);
    return test_summary();
}
