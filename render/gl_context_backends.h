// The GlContext implementations; create_context() picks one. Internal
// to render/: each lives in its own file so only that file sees its system
// headers (OSMesa's GL/gl.h and glad's gl.h cannot share a translation unit).
#pragma once

#include "render/gl_context.h"

namespace render::detail {

std::unique_ptr<GlContext> create_osmesa_context();
// hardware: the first hardware device of the device platform (Backend::gpu);
// else Mesa's software device or a software surfaceless display (Backend::egl).
std::unique_ptr<GlContext> create_egl_context(bool hardware);
std::vector<EglDevice> query_egl_devices();
std::unique_ptr<GlContext> create_glfw_context(const ContextOptions& options);

// Sets the process environment Mesa reads when it creates its first context,
// unless the user set it: a fixed llvmpipe thread count (LP_NUM_THREADS) and,
// when `software`, the software rasteriser (LIBGL_ALWAYS_SOFTWARE), so that
// EGL draws with llvmpipe as OSMesa does; the gpu backend leaves it unset.
void prepare_mesa_environment(bool software);

}  // namespace render::detail
