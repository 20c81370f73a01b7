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
    fs_status st;
    GLuint vs = compile_stage(GL_VERTEX_SHADER, d->vs, d, &st);
    if (!vs)
        return st;
    GLuint fs = compile_stage(GL_FRAGMENT_SHADER, d->fs, d, &st);
    if (!fs) {
        glDeleteShader(vs);
        return st;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        log_error("%s + %s (%s): link failed: %s", d->vs, d->fs, d->label ? d->label : "-", log);
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
