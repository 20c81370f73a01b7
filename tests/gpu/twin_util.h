/* twin_util.h: running a GLSL twin on the GPU for the twin tests (header only): a compute shader
 * reads `count` inputs from SSBO binding 0 and writes outputs to binding 1 (local size 64,
 * uniform u_count), and the results come back for comparison with the C twin. */
#ifndef FOVSIM_TWIN_UTIL_H
#define FOVSIM_TWIN_UTIL_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "gl/gl_program.h"

/* Compiles `path` (an embedded .comp), runs it over `count` inputs, reads `out`. False (with the
 * compiler's message on stderr) when anything fails. */
static inline bool twin_run(const char *path, const void *in, size_t in_bytes, void *out, size_t out_bytes,
                            unsigned count)
{
    gpu_program_handle h;
    if (gl_program_build(&(gl_program_desc){.cs = path, .label = "twin test"}, &h) != FS_OK)
        return false;
    GLuint buf[2];
    glCreateBuffers(2, buf);
    glNamedBufferStorage(buf[0], (GLsizeiptr)in_bytes, in, 0);
    glNamedBufferStorage(buf[1], (GLsizeiptr)out_bytes, NULL, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buf[1]);
    glUseProgram(h.id);
    glUniform1ui(glGetUniformLocation(h.id, "u_count"), (GLuint)count);
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buf[1], 0, (GLsizeiptr)out_bytes, out);
    GLenum err = glGetError();
    glDeleteBuffers(2, buf);
    gl_program_destroy(h);
    return err == GL_NO_ERROR;
}

/* Deterministic inputs: splitmix64. */
static uint64_t rng_state = 0x2545f4914f6cdd1dull;

static inline uint64_t rng_u64(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static inline double rng01(void)
{
    return (double)(rng_u64() >> 11) * (1.0 / 9007199254740992.0);
}

static inline float rngf(double lo, double hi)
{
    return (float)(lo + (hi - lo) * rng01());
}

static inline bool twin_same_bits(float a, float b)
{
    uint32_t x, y;
    memcpy(&x, &a, 4);
    memcpy(&y, &b, 4);
    return x == y;
}

#endif
