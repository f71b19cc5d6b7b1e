// Errors the renderer raises. Nothing in render/ prints or exits: the
// `plausible` command turns a RenderError into a message and an exit code
// (bad_input and no_display: 2, docs/design.md "The command").
#pragma once

#include <stdexcept>
#include <string>

namespace render {

enum class ErrorKind {
    bad_input,    // an image size, a path, a draw list the renderer cannot take
    no_display,   // a window was asked for where there is no display
    unavailable,  // a backend or a file the renderer needs is not on this machine
    gl,           // the GL driver refused (shader compile, framebuffer incomplete)
};

class RenderError : public std::runtime_error {
public:
    RenderError(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
    ErrorKind kind() const { return kind_; }

private:
    ErrorKind kind_;
};

}  // namespace render
