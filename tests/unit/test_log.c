/* The logger's escaping (a message is always one line: README "Limits"): input quoted in a message can neither break the line
 * nor reach the terminal as a control sequence; printable ASCII and well-formed UTF-8 pass. */
#include <stdio.h>
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

/* Messages are bounded (README "Limits"). log_quote keeps at most cap - 6 bytes, never half a UTF-8
 * character, and shows a NUL byte as \x00; log_bounded_write shortens a long run without blanks
 * to its head and tail and caps the whole message. */
TEST(quoted_input_is_bounded)
{
    char q[16];
    CHECK(strcmp(log_quote(q, sizeof q, "short", 5), "'short'") == 0);
    CHECK(strcmp(log_quote(q, sizeof q, "0123456789abcdef", 16), "'0123456789...'") == 0);
    /* 8 ASCII bytes, then a 3-byte character that does not fit whole in the 10 allowed */
    CHECK(strcmp(log_quote(q, sizeof q, "abcdefgh\xe2\x80\x94z", 12), "'abcdefgh...'") == 0);
    CHECK(strcmp(log_quote(q, sizeof q, "a\0b", 3), "'a\\x00b'") == 0);

    size_t n = (size_t)8 << 20;
    char *big = malloc(n + 64);
    CHECK(big != NULL);
    if (!big)
        return;
    memcpy(big, "a.gltf: URI ", 12);
    memset(big + 12, 'A', n);
    memcpy(big + 12 + n, " in Buffer", 10);
    char *out = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&out, &len);
    CHECK(f != NULL);
    if (f) {
        log_bounded_write(f, big, n + 22);
        fclose(f);
        CHECK(len < LOG_MAX_RUN + 64);
        CHECK(out && strncmp(out, "a.gltf: URI AAAA", 16) == 0 && strstr(out, "...[") && strstr(out, "A in Buffer"));
    }
    free(out);
    /* many short words: the whole message is capped */
    for (size_t i = 0; i < n; i++)
        big[i] = i % 4 == 3 ? ' ' : 'w';
    out = NULL;
    f = open_memstream(&out, &len);
    CHECK(f != NULL);
    if (f) {
        log_bounded_write(f, big, n);
        fclose(f);
        CHECK(len <= LOG_MAX_MESSAGE + 40);
        CHECK(out && strstr(out, "bytes more]"));
    }
    free(out);
    free(big);
}

int main(void)
{
    RUN(printable_text_passes);
    RUN(control_characters_are_escaped);
    RUN(malformed_utf8_and_c1_controls_are_escaped);
    RUN(quoted_input_is_bounded);
    return test_summary();
}
