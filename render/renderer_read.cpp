// Reading frames back (see renderer.h: read_back, queue_read_back): through
// pixel-buffer objects, in the framebuffer's own layout (BGRA bytes, bottom
// row first), which drivers copy without converting pixel by pixel (llvmpipe:
// 1.8 ms for 1280x720 where GL_RGB straight into memory took 15); the
// reordering into RGB or RGBA rows, top first, is one pass on the CPU.
#include "render/renderer_impl.h"

#include <chrono>
#include <cstdint>
#include <string>

namespace render {
namespace {

// Bottom-up BGRA rows into top-down RGB (channels 3) or RGBA rows.
void to_image(const std::uint8_t* bgra, int width, int height, int channels, std::uint8_t* out) {
    const std::size_t in_row = static_cast<std::size_t>(width) * 4;
    const std::size_t out_row = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
    for (int y = 0; y < height; ++y) {
        const std::uint8_t* __restrict in = bgra + static_cast<std::size_t>(height - 1 - y) * in_row;
        std::uint8_t* __restrict o = out + static_cast<std::size_t>(y) * out_row;
        if (channels == 4) {
            for (int x = 0; x < width; ++x) {
                o[4 * x] = in[4 * x + 2], o[4 * x + 1] = in[4 * x + 1], o[4 * x + 2] = in[4 * x];
                o[4 * x + 3] = in[4 * x + 3];
            }
        } else {
            for (int x = 0; x < width; ++x) {
                o[3 * x] = in[4 * x + 2], o[3 * x + 1] = in[4 * x + 1], o[3 * x + 2] = in[4 * x];
            }
        }
    }
}

void check_channels(int channels, const char* what) {
    if (channels != 3 && channels != 4) {
        throw RenderError(ErrorKind::bad_input,
                          std::string(what) + ": channels must be 3 or 4 (got " + std::to_string(channels) + ")");
    }
}

}  // namespace

// Queues the read of `framebuffer` (0: the window's back buffer) into a
// pixel-pack buffer; GL runs it after the commands before it, and the caller
// may go on drawing. A free buffer's storage is kept where it holds the
// frame: a read is always collected (mapped, finish_read) before its buffer
// is free again, so nothing can still be using it.
Renderer::Impl::PendingRead Renderer::Impl::start_read(GLuint framebuffer, const char* what) {
    context.make_current();
    // The window shows the frame at the size asked; the targets hold it at its scale.
    const int w = framebuffer == 0 ? view_width : width;
    const int h = framebuffer == 0 ? view_height : height;
    PendingRead read{{}, w, h};
    if (free_buffers.empty()) {
        gl.GenBuffers(1, &read.pack.buffer);
    } else {
        read.pack = free_buffers.back();
        free_buffers.pop_back();
    }
    const std::size_t bytes = 4 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    gl.BindBuffer(GL_PIXEL_PACK_BUFFER, read.pack.buffer);
    if (read.pack.storage < bytes) {
        gl.BufferData(GL_PIXEL_PACK_BUFFER, static_cast<GLsizeiptr>(bytes), nullptr, GL_STREAM_READ);
        read.pack.storage = bytes;
    }
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    gl.ReadBuffer(framebuffer == 0 ? GL_BACK : GL_COLOR_ATTACHMENT0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl.ReadPixels(0, 0, w, h, GL_BGRA, GL_UNSIGNED_BYTE, nullptr);
    gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    try {
        check_errors(what);
    } catch (const RenderError&) {
        free_buffers.push_back(read.pack);  // deleted with the others
        throw;
    }
    return read;
}

// Waits for the read, and puts its pixels into `into` (its storage reused
// where it holds them); the buffer is free again.
void Renderer::Impl::finish_read(const PendingRead& read, int channels, const char* what, Image& into) {
    context.make_current();
    into.width = read.width;
    into.height = read.height;
    into.channels = channels;
    into.pixels.resize(static_cast<std::size_t>(read.width) * static_cast<std::size_t>(read.height) *
                       static_cast<std::size_t>(channels));
    const auto bytes =
        static_cast<GLsizeiptr>(4 * static_cast<std::size_t>(read.width) * static_cast<std::size_t>(read.height));
    gl.BindBuffer(GL_PIXEL_PACK_BUFFER, read.pack.buffer);
    const void* mapped = gl.MapBufferRange(GL_PIXEL_PACK_BUFFER, 0, bytes, GL_MAP_READ_BIT);
    if (mapped != nullptr) {
        to_image(static_cast<const std::uint8_t*>(mapped), read.width, read.height, channels, into.pixels.data());
        gl.UnmapBuffer(GL_PIXEL_PACK_BUFFER);
    }
    gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    free_buffers.push_back(read.pack);
    check_errors(what);
    if (mapped == nullptr) throw RenderError(ErrorKind::gl, std::string("cannot map the pixel buffer while ") + what);
}

Image Renderer::read_back(int channels) {
    check_channels(channels, "read_back");
    if (!impl_->has_frame) throw RenderError(ErrorKind::bad_input, "read_back: nothing has been drawn yet");
    const auto start = std::chrono::steady_clock::now();
    Image image;
    impl_->finish_read(impl_->start_read(impl_->resolve_fbo, "reading the frame back"), channels,
                       "reading the frame back", image);
    if (impl_->time_passes) {
        impl_->stats.passes.read_back =
            1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return image;
}

void Renderer::queue_read_back() {
    if (!impl_->has_frame) throw RenderError(ErrorKind::bad_input, "queue_read_back: nothing has been drawn yet");
    if (impl_->queued_reads.size() >= kMaxQueuedReads) {
        throw RenderError(ErrorKind::bad_input, "queue_read_back: " + std::to_string(kMaxQueuedReads) +
                                                    " frames are queued already (take_read_back first)");
    }
    impl_->queued_reads.push_back(impl_->start_read(impl_->resolve_fbo, "queueing the frame's read-back"));
    // Hand the frame to the renderer's threads now: the caller goes on (the
    // next frame's physics) while they draw it.
    impl_->gl.Flush();
}

std::size_t Renderer::queued_read_backs() const { return impl_->queued_reads.size(); }

Image Renderer::take_read_back(int channels) {
    Image image;
    take_read_back(image, channels);
    return image;
}

void Renderer::take_read_back(Image& into, int channels) {
    check_channels(channels, "take_read_back");
    if (impl_->queued_reads.empty()) throw RenderError(ErrorKind::bad_input, "take_read_back: no frame is queued");
    const auto start = std::chrono::steady_clock::now();
    const Impl::PendingRead read = impl_->queued_reads.front();
    impl_->queued_reads.pop_front();
    impl_->finish_read(read, channels, "reading a queued frame back", into);
    if (impl_->time_passes) {
        impl_->stats.passes.read_back =
            1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
}

Image Renderer::read_window(int channels) {
    check_channels(channels, "read_window");
    if (impl_->context.window() == nullptr)
        throw RenderError(ErrorKind::bad_input, "read_window: this context has no window");
    if (!impl_->has_frame) throw RenderError(ErrorKind::bad_input, "read_window: nothing has been drawn yet");
    Image image;
    impl_->finish_read(impl_->start_read(0, "reading the window back"), channels, "reading the window back", image);
    return image;
}

}  // namespace render
