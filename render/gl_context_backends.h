// The three GlContext implementations; create_context() picks one. Internal
// to render/: each lives in its own file so only that file sees its system
// headers (OSMesa's GL/gl.h and glad's gl.h cannot share a translation unit).
#pragma once

#include "render/gl_context.h"

namespace render::detail {

std::unique_ptr<GlContext> create_osmesa_context();
std::unique_ptr<GlContext> create_egl_context();
std::unique_ptr<GlContext> create_glfw_context(const ContextOptions& options);

// Sets the process environment Mesa reads when it creates its first context,
// unless the user set it: a fixed llvmpipe thread count (LP_NUM_THREADS) and,
// for EGL, the software rasteriser, so every backend draws with llvmpipe.
void prepare_mesa_environment();

}  // namespace render::detail
