// Frames per second of the renderer on the default off-screen backend (OSMesa
// where built, else EGL; llvmpipe either way): 200 spheres over the
// ground with the shadow map, at 640x480 and 1280x720, MSAA off and 4x, with
// and without reading the frame back. The target: 1280x720, 4x MSAA,
// with read-back, >= 20 frames/s on 2 cores. Run with `make bench`; the figure
// to read is `fps`.
#include "render/renderer.h"
#include "tests/render/draw_lists.h"

#include <benchmark/benchmark.h>

namespace {

render::GlContext& context() {
    static const auto c = render::create_context({.backend = render::default_backend()});
    return *c;
}

render::Renderer& renderer() {
    static render::Renderer r(context());
    return r;
}

// Arguments: width, height, MSAA samples, read back (0/1).
void frame(benchmark::State& state) {
    const render::RenderSettings settings{.width = static_cast<int>(state.range(0)),
                                          .height = static_cast<int>(state.range(1)),
                                          .msaa_samples = static_cast<int>(state.range(2))};
    const bool read_back = state.range(3) != 0;
    const render::DrawList list = render::testing::sphere_field(200);
    render::Renderer& r = renderer();
    r.draw(list, settings);  // warm-up: targets allocated, shaders compiled by the driver
    for (auto _ : state) {
        r.draw(list, settings);
        if (read_back) {
            benchmark::DoNotOptimize(r.read_back(3).pixels.data());
        } else {
            r.finish();  // llvmpipe draws when the frame is flushed: wait for it
        }
    }
    state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["triangles"] = static_cast<double>(r.last_frame().triangles);
}

BENCHMARK(frame)
    ->ArgNames({"w", "h", "msaa", "readback"})
    ->ArgsProduct({{640}, {480}, {0, 4}, {0, 1}})
    ->ArgsProduct({{1280}, {720}, {0, 4}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
