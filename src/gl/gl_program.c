#include "gl/gl_program.h"

#include <epoxy/gl.h>
#include <stddef.h>

#include "core/log.h"
#include "gl/shader_src.h"

static GLuint compile_stage(GLenum stage, const char *path, const gl_program_desc *d, fs_status *st)
{
    shader_src src;
    *st = shader_src_build(path, d->defines, d->define_count, &src);
    if (*st != FS_OK)
        return 0;
    GLuint sh = glCreateShader(stage);
    const char *text = src.text;
    glShaderSource(sh, 1, &text, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096], out[8192];
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        shader_src_translate_log(&src, log, out, sizeof out);
        log_error("%s (%s): shader compile failed: %s", path, d->label ? d->label : "-", out);
        glDeleteShader(sh);
        sh = 0;
        *st = FS_ERR_SHADER;
    }
    shader_src_free(&src);
    return sh;
}

fs_status gl_program_build(const gl_program_desc *d, gpu_program_handle *out)
{
    out->id = 0;
    fs_status st = FS_OK;
    GLuint stages[3] = {0, 0, 0};
    int n = 0;
    if (d->cs) {
        stages[n++] = compile_stage(GL_COMPUTE_SHADER, d->cs, d, &st);
    } else {
        stages[n++] = compile_stage(GL_VERTEX_SHADER, d->vs, d, &st);
        if (stages[0] && d->gs)
            stages[n++] = compile_stage(GL_GEOMETRY_SHADER, d->gs, d, &st);
        if (stages[n - 1])
            stages[n++] = compile_stage(GL_FRAGMENT_SHADER, d->fs, d, &st);
    }
    if (!stages[n - 1]) {
        for (int i = 0; i < n; i++)
            glDeleteShader(stages[i]);
        return st;
    }
    GLuint p = glCreateProgram();
    for (int i = 0; i < n; i++) {
        glAttachShader(p, stages[i]);
        glDeleteShader(stages[i]); /* flagged; freed with the program */
    }
    glLinkProgram(p);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        log_error("%s%s%s (%s): link failed: %s", d->cs ? d->cs : d->vs, d->cs ? "" : " + ", d->cs ? "" : d->fs,
                  d->label ? d->label : "-", log);
        glDeleteProgram(p);
        return FS_ERR_SHADER;
    }
    out->id = p;
    return FS_OK;
}

void gl_program_destroy(gpu_program_handle p)
{
    if (p.id)
        glDeleteProgram(p.id);
}
