// Frames per second of the renderer on the default off-screen backend (OSMesa
// where built, else EGL; llvmpipe either way): 200 spheres over the
// ground with the shadow map, at 640x480 and 1280x720, MSAA off and 4x, with
// and without reading the frame back. The target: 1280x720, 4x MSAA,
// with read-back, >= 20 frames/s on 2 cores. Run with `make bench`; the figure
// to read is `fps`; the ms_ counters are a frame pass by pass (measured apart,
// each pass waiting for the GPU: issue 21's "measure first").
//
// Every timed frame is drawn whole: one sphere moves by a millimetre each
// frame, as a running scene's do, so that neither the frame nor the shadow
// map is the last one's (the renderer reuses them when nothing changed), and
// the benchmark reports an error if a frame or its shadow map was reused.
#include "render/renderer.h"
#include "tests/render/draw_lists.h"

#include <benchmark/benchmark.h>

#include <cstdint>

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
    render::DrawList list = render::testing::sphere_field(200);
    render::Renderer& r = renderer();
    r.draw(list, settings);              // warm-up: targets allocated, shaders compiled by the driver
    std::int64_t drawn = 0, reused = 0;  // frames; those (or their shadow maps) the renderer did not draw
    auto next = [&] {
        list.spheres[0].center.y() += (++drawn % 2 == 0 ? 0.001f : -0.001f);  // m
        r.draw(list, settings);
        reused += r.last_frame().frame_reused || r.last_frame().shadow_reused;
    };
    for (auto _ : state) {
        next();
        if (read_back) {
            benchmark::DoNotOptimize(r.read_back(3).pixels.data());
        } else {
            r.finish();  // llvmpipe draws when the frame is flushed: wait for it
        }
    }
    if (reused != 0) {
        state.SkipWithError("a frame or shadow map was reused: the benchmark timed less than a frame");
        return;
    }
    state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["triangles"] = static_cast<double>(r.last_frame().triangles);
    // One more frame, pass by pass (each pass waits for the GPU: ms of its
    // own, not of the frame rate above): what each change would save.
    r.time_passes(true);
    render::Renderer::PassTimes sum;
    constexpr int kTimed = 5;
    for (int k = 0; k < kTimed; ++k) {
        next();
        if (read_back) benchmark::DoNotOptimize(r.read_back(3).pixels.data());
        sum.add(r.last_frame().passes, 1.0 / kTimed);
    }
    r.time_passes(false);
    state.counters["ms_shadow"] = sum.shadow;
    state.counters["ms_opaque"] = sum.ground + sum.opaque;
    state.counters["ms_impostors"] = sum.impostors;
    state.counters["ms_overlays"] = sum.overlays;
    state.counters["ms_resolve"] = sum.resolve;
    state.counters["ms_readback"] = sum.read_back;
    state.counters["ms_prepare"] = sum.prepare;
}

BENCHMARK(frame)
    ->ArgNames({"w", "h", "msaa", "readback"})
    ->ArgsProduct({{640}, {480}, {0, 4}, {0, 1}})
    ->ArgsProduct({{1280}, {720}, {0, 4}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
