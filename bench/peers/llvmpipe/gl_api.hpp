// llvmpipe/gl_api.hpp — the OpenGL 4.5 entry points the peer calls, loaded by eglGetProcAddress.
//
// Takes: a current EGL context. Gives: a table of function pointers (gl.Finish() calls
// glFinish), or the name of the first entry point the driver does not export. No loader
// library is needed: EGL_KHR_get_all_proc_addresses (Mesa has it) returns core functions too.
#pragma once

#include <GL/glcorearb.h>

namespace mosaic::peers {

// X(Name, NAME): the GL function glName with its glcorearb.h pointer type PFNGLNAMEPROC.
#define MOSAIC_PEER_GL_FUNCTIONS(X)                                           \
  X(GetString, GETSTRING)                                                     \
  X(GetIntegerv, GETINTEGERV)                                                 \
  X(GetFloatv, GETFLOATV)                                                     \
  X(GetError, GETERROR)                                                       \
  X(ClipControl, CLIPCONTROL)                                                 \
  X(Viewport, VIEWPORT)                                                       \
  X(Enable, ENABLE)                                                           \
  X(Disable, DISABLE)                                                         \
  X(DepthFunc, DEPTHFUNC)                                                     \
  X(DepthMask, DEPTHMASK)                                                     \
  X(CullFace, CULLFACE)                                                       \
  X(FrontFace, FRONTFACE)                                                     \
  X(CreateBuffers, CREATEBUFFERS)                                             \
  X(NamedBufferStorage, NAMEDBUFFERSTORAGE)                                   \
  X(DeleteBuffers, DELETEBUFFERS)                                             \
  X(CreateVertexArrays, CREATEVERTEXARRAYS)                                   \
  X(DeleteVertexArrays, DELETEVERTEXARRAYS)                                   \
  X(VertexArrayVertexBuffer, VERTEXARRAYVERTEXBUFFER)                         \
  X(VertexArrayAttribFormat, VERTEXARRAYATTRIBFORMAT)                         \
  X(VertexArrayAttribBinding, VERTEXARRAYATTRIBBINDING)                       \
  X(EnableVertexArrayAttrib, ENABLEVERTEXARRAYATTRIB)                         \
  X(BindVertexArray, BINDVERTEXARRAY)                                         \
  X(CreateShader, CREATESHADER)                                               \
  X(ShaderSource, SHADERSOURCE)                                               \
  X(CompileShader, COMPILESHADER)                                             \
  X(GetShaderiv, GETSHADERIV)                                                 \
  X(GetShaderInfoLog, GETSHADERINFOLOG)                                       \
  X(DeleteShader, DELETESHADER)                                               \
  X(CreateProgram, CREATEPROGRAM)                                             \
  X(AttachShader, ATTACHSHADER)                                               \
  X(LinkProgram, LINKPROGRAM)                                                 \
  X(GetProgramiv, GETPROGRAMIV)                                               \
  X(GetProgramInfoLog, GETPROGRAMINFOLOG)                                     \
  X(DeleteProgram, DELETEPROGRAM)                                             \
  X(UseProgram, USEPROGRAM)                                                   \
  X(ProgramUniform1f, PROGRAMUNIFORM1F)                                       \
  X(CreateRenderbuffers, CREATERENDERBUFFERS)                                 \
  X(NamedRenderbufferStorageMultisample, NAMEDRENDERBUFFERSTORAGEMULTISAMPLE) \
  X(GetNamedRenderbufferParameteriv, GETNAMEDRENDERBUFFERPARAMETERIV)         \
  X(DeleteRenderbuffers, DELETERENDERBUFFERS)                                 \
  X(CreateFramebuffers, CREATEFRAMEBUFFERS)                                   \
  X(NamedFramebufferRenderbuffer, NAMEDFRAMEBUFFERRENDERBUFFER)               \
  X(CheckNamedFramebufferStatus, CHECKNAMEDFRAMEBUFFERSTATUS)                 \
  X(NamedFramebufferReadBuffer, NAMEDFRAMEBUFFERREADBUFFER)                   \
  X(DeleteFramebuffers, DELETEFRAMEBUFFERS)                                   \
  X(BindFramebuffer, BINDFRAMEBUFFER)                                         \
  X(ClearNamedFramebufferfv, CLEARNAMEDFRAMEBUFFERFV)                         \
  X(BlitNamedFramebuffer, BLITNAMEDFRAMEBUFFER)                               \
  X(GetMultisamplefv, GETMULTISAMPLEFV)                                       \
  X(DrawArrays, DRAWARRAYS)                                                   \
  X(Finish, FINISH)                                                           \
  X(PixelStorei, PIXELSTOREI)                                                 \
  X(ReadPixels, READPIXELS)                                                   \
  X(CreateQueries, CREATEQUERIES)                                             \
  X(DeleteQueries, DELETEQUERIES)                                             \
  X(BeginQuery, BEGINQUERY)                                                   \
  X(EndQuery, ENDQUERY)                                                       \
  X(GetQueryObjectui64v, GETQUERYOBJECTUI64V)

/// The entry points, one member per function: gl.Name(...) calls glName.
struct GlApi {
#define MOSAIC_PEER_GL_MEMBER(Name, NAME) PFNGL##NAME##PROC Name = nullptr;
  MOSAIC_PEER_GL_FUNCTIONS(MOSAIC_PEER_GL_MEMBER)
#undef MOSAIC_PEER_GL_MEMBER

  /// Loads every entry point from the current context. Returns nullptr on success, else the
  /// name ("glClipControl") of the first one that is missing.
  const char* load();
};

}  // namespace mosaic::peers
