#include "scenes/video/video.h"

#include "render/font.h"
#include "render/gl_context.h"
#include "render/renderer.h"
#include "scenes/common/child_process.h"
#include "scenes/common/interrupt.h"
#include "scenes/common/output_file.h"
#include "scenes/common/progress.h"
#include "scenes/draw/scene_run.h"
#include "scenes/video/ahead.h"
#include "sim/error.h"
#include "sim/integrators.h"
#include "sim/rigid.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace scenes {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The longest video, s simulated: an hour is 216,000 frames at 60 fps.
constexpr double kMaxVideoSeconds = 3600.0;

void validate(const VideoOptions& o) {
    const std::string ext = o.output.extension().string();
    if (ext != ".mp4" && ext != ".gif") {
        throw sim::InputError("video: -o must end in .mp4 or .gif (got '" + o.output.string() + "')");
    }
    if (o.width < 16 || o.height < 16 || o.width > 7680 || o.height > 4320 || o.width % 2 != 0 || o.height % 2 != 0) {
        throw sim::InputError(
            "video: --size must be even, within 16x16 .. 7680x4320 (H.264 with yuv420p needs even "
            "sides; got " +
            std::to_string(o.width) + "x" + std::to_string(o.height) + ")");
    }
    if (o.fps < 1 || o.fps > 120)
        throw sim::InputError("video: --fps must be within 1 .. 120 (got " + std::to_string(o.fps) + ")");
    if (!std::isfinite(o.seconds) || o.seconds < 0.0 || o.seconds > kMaxVideoSeconds) {
        throw sim::InputError("video: --seconds must be within 0 .. " + sim::format_value(kMaxVideoSeconds) + " (got " +
                              sim::format_value(o.seconds) + ")");
    }
    if (o.compare.size() > 6) throw sim::InputError("video: --compare takes at most 6 tiles");
    for (const std::string& name : o.compare) {
        if (name.find('=') != std::string::npos) {
            parse_override(name);  // a --set variant, KEY=VALUE (the scene's loader checks the rest)
        } else if (!sim::integrator_from_name(name)) {
            std::string known;
            for (const auto& info : sim::kIntegrators) known += (known.empty() ? "" : ", ") + std::string(info.name);
            throw sim::InputError("video: --compare: unknown integrator '" + name + "' (one of " + known +
                                  "; or a --set variant KEY=VALUE)");
        }
    }
    check_output(o.output);  // a folder, a FIFO, a device, /proc: refused before any frame
}

// Copies `tile` into `frame` with its top-left corner at (x0, y0).
void blit(render::Image& frame, const render::Image& tile, int x0, int y0) {
    const std::size_t row = static_cast<std::size_t>(tile.width) * tile.channels;
    for (int y = 0; y < tile.height; ++y) std::memcpy(frame.at(x0, y0 + y), tile.at(0, y), row);
}

std::string read_all(const fs::path& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// `text` in lines of at most `width` px at text height `size` px (a glyph is
// about 0.55 size wide on average), broken between words.
std::vector<std::string> wrap(const std::string& text, float width, float size) {
    const auto chars = static_cast<std::size_t>(std::max(10.0f, width / (0.55f * size)));
    std::vector<std::string> lines;
    std::istringstream words(text);
    std::string line, word;
    while (words >> word) {
        if (!line.empty() && line.size() + 1 + word.size() > chars) {
            lines.push_back(line);
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty()) lines.push_back(line);
    return lines;
}

// Side by side, plots of the same quantity share their axes (the energy of
// forward Euler against symplectic Euler's on one scale: the lesson is the
// difference), so each plot's range becomes the union over the tiles.
void share_plot_ranges(std::vector<render::DrawList>& lists) {
    if (lists.size() < 2) return;
    std::map<std::string, std::array<float, 4>> range;  // title -> x min, x max, y min, y max
    for (const render::DrawList& list : lists) {
        for (const render::Plot& plot : list.plots) {
            auto [it, fresh] =
                range.try_emplace(plot.title, std::array<float, 4>{INFINITY, -INFINITY, INFINITY, -INFINITY});
            auto& r = it->second;
            for (const auto& series : plot.series) {
                for (const render::Vec2& p : series.points) {
                    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) continue;
                    r = {std::min(r[0], p.x()), std::max(r[1], p.x()), std::min(r[2], p.y()), std::max(r[3], p.y())};
                }
            }
        }
    }
    for (render::DrawList& list : lists) {
        for (render::Plot& plot : list.plots) {
            const auto& r = range.at(plot.title);
            if (!(r[3] > r[2])) continue;  // flat or empty: each fits its own
            const float pad = 0.05f * (r[3] - r[2]);
            plot.y_range = render::Vec2(r[2] - pad, r[3] + pad);
            if (!plot.x_range && r[1] > r[0]) plot.x_range = render::Vec2(r[0], r[1]);
        }
    }
}

// The compare grid's free cells (3 tiles in a 2 x 2 grid): the scene's name,
// its description and the integrators in tile order, drawn once.
void title_card(render::Image& frame, const SceneDef& scene, const std::vector<std::string>& compare, int x0, int y0,
                int w) {
    const render::Font& font = render::Font::default_font();
    const float size = std::max(12.0f, static_cast<float>(w) / 28.0f);  // px
    const render::Rgba8 light{235, 235, 235, 255}, dim{170, 175, 185, 255};
    const float left = static_cast<float>(x0) + size;
    float y = static_cast<float>(y0) + size;
    render::draw_text(frame, font, scene.name, left, y, 1.6f * size, light);
    y += 2.6f * size;
    // The description, wrapped to the cell.
    for (const std::string& line : wrap(scene.description, static_cast<float>(w) - 2 * size, size)) {
        render::draw_text(frame, font, line, left, y, size, dim);
        y += 1.4f * size;
    }
    y += 2.4f * size;
    std::string order = "Tiles: ";
    for (std::size_t i = 0; i < compare.size(); ++i) order += (i ? ", " : "") + compare[i];
    render::draw_text(frame, font, order, left, y, size, light);
}

// One description per tile, each with its variant's overrides (a run holds a
// reference to its description, so they live apart).
std::vector<std::unique_ptr<SceneDef>> tile_scenes(const SceneDef& scene, const std::vector<Override>& overrides,
                                                   const VideoOptions& options) {
    std::vector<std::unique_ptr<SceneDef>> defs;
    if (options.compare.empty()) {
        defs.push_back(std::make_unique<SceneDef>(scene));
        return defs;
    }
    if (scene.recorded) {
        throw sim::InputError(
            "video: --compare makes variants of a scene file; a recording replays one run "
            "(give the scene's .toml to compare)");
    }
    for (const std::string& name : options.compare) {
        std::vector<Override> with = overrides;
        if (name.find('=') != std::string::npos) {
            with.push_back(parse_override(name));
        } else {
            with.push_back({"step.integrator", "\"" + name + "\""});
        }
        try {
            defs.push_back(std::make_unique<SceneDef>(load_scene(scene.file, with)));
        } catch (const SceneError& e) {
            throw sim::InputError("video: --compare " + name + ": " + e.what());
        }
    }
    return defs;
}

// Where the tiles go. They keep the video's aspect ratio (a scene's camera is
// framed for it): the grid that gives them the largest size, side by side on
// a tie, centred in the frame.
struct TileGrid {
    int n = 1, cols = 1, rows = 1;
    int tile_w = 0, tile_h = 0;  // px, even
    int width = 0, height = 0;   // px, the frame's
    int x(int i) const { return (i % cols) * tile_w + (width - cols * tile_w) / 2; }
    int y(int i) const { return (i / cols) * tile_h + (height - rows * tile_h) / 2; }
};

TileGrid tile_grid(int n, const VideoOptions& options) {
    TileGrid g;
    g.n = n;
    g.rows = n;
    g.width = options.width;
    g.height = options.height;
    const double aspect = static_cast<double>(options.width) / options.height;
    for (int c = n; c >= 1; --c) {
        const int r = (n + c - 1) / c;
        const int w = static_cast<int>(std::min(static_cast<double>(options.width) / c, options.height / r * aspect));
        if (w > g.tile_w) g.cols = c, g.rows = r, g.tile_w = w;
    }
    g.tile_w &= ~1;
    g.tile_h = static_cast<int>(g.tile_w / aspect) & ~1;
    return g;
}

// The texts a tile gets besides its HUD: a --set variant's label, and the
// scene's description as a caption for the first seconds (unless a compare
// grid's free cell shows it already).
struct TileTexts {
    bool caption = false;
    double caption_seconds = 0.0;  // s of video
    float text = 13.0f;            // px, as the HUD's
    std::string caption_text;      // the description wrapped to the tile
    float caption_height = 0.0f;   // px

    TileTexts(const SceneDef& scene, const VideoOptions& options, const TileGrid& grid, double seconds)
        : caption(options.caption && !scene.description.empty() && grid.cols * grid.rows == grid.n),
          caption_seconds(std::min(4.0, 0.4 * seconds)),
          text(std::max(13.0f, static_cast<float>(grid.tile_h) / 22.0f)) {
        for (const std::string& line : wrap(scene.description, 0.9f * static_cast<float>(grid.tile_w), 0.8f * text))
            caption_text += (caption_text.empty() ? "" : "\n") + line;
        // 1.25 lines of 0.8 text each
        caption_height =
            0.8f * text * 1.25f * static_cast<float>(std::count(caption_text.begin(), caption_text.end(), '\n') + 1);
    }

    // Adds tile i's texts at video time t (s) to its draw list.
    void add(render::DrawList& list, const VideoOptions& options, std::size_t i, int tile_h, double t) const {
        const bool labelled = !options.compare.empty() && options.compare[i].find('=') != std::string::npos;
        if (labelled) {
            // A --set variant: the HUD shows integrator and dt, the label what else differs.
            list.texts.push_back(render::Text{"--set " + options.compare[i],
                                              render::Vec2(0.5f * text, static_cast<float>(tile_h) - 1.6f * text),
                                              0.85f * text, render::Color{0.1f, 0.1f, 0.12f, 1}, true});
        }
        if (caption && t < caption_seconds) {
            // The first seconds say what the scene shows, across the bottom.
            list.texts.push_back(render::Text{caption_text,
                                              render::Vec2(0.5f * text, static_cast<float>(tile_h) - caption_height -
                                                                            (labelled ? 2.2f : 0.8f) * text),
                                              0.8f * text, render::Color{0.1f, 0.1f, 0.12f, 1}, true});
        }
    }
};

// Whether the video ffmpeg wrote is whole: an MP4's top-level boxes tile the
// file exactly and one is its index (moov); a GIF ends with its trailer.
// ffmpeg has exited 0 on a file cut short by a file size limit.
bool whole_video(const fs::path& file, bool gif) {
    std::ifstream in(file, std::ios::binary);
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (!in || ec || size < 8) return false;
    if (gif) {
        in.seekg(static_cast<std::streamoff>(size - 1));
        return in.get() == 0x3B;
    }
    bool index = false;
    for (std::uintmax_t at = 0; at < size;) {
        unsigned char head[16];
        in.seekg(static_cast<std::streamoff>(at));
        if (!in.read(reinterpret_cast<char*>(head), 8)) return false;
        std::uint64_t box = 0;
        for (int k = 0; k < 4; ++k) box = (box << 8) | head[k];
        std::size_t header = 8;
        if (box == 1) {  // a 64-bit size follows the type
            if (!in.read(reinterpret_cast<char*>(head + 8), 8)) return false;
            box = 0;
            for (int k = 8; k < 16; ++k) box = (box << 8) | head[k];
            header = 16;
        } else if (box == 0) {
            box = size - at;  // to the end of the file
        }
        if (box < header || box > size - at) return false;
        index = index || std::memcmp(head + 4, "moov", 4) == 0;
        at += box;
    }
    return index;
}

// ffmpeg behind a pipe, writing a temporary file (and its log) beside the
// output; finish() renames it into place. Destroyed unfinished (an error, an
// interrupt), it leaves nothing behind. Frames go to ffmpeg from a thread of
// their own, so that the next frame is drawn while this one is written (the
// pipe blocks whenever ffmpeg is busy); at most kQueued wait their turn.
class Encoder {
public:
    explicit Encoder(const VideoOptions& options)
        : options_(options), output_(options.output), log_(output_.temporary().string() + ".log") {}
    ~Encoder() {
        {
            const std::lock_guard lock(mutex_);
            queue_.clear();  // unfinished: what waits is not written
        }
        stop_writer();
        ffmpeg_.reset();
        std::error_code ec;
        fs::remove(log_, ec);
    }
    Encoder(const Encoder&) = delete;
    Encoder& operator=(const Encoder&) = delete;

    bool started() const { return ffmpeg_ != nullptr; }
    void start(int channels) {
        try {
            ffmpeg_ = std::make_unique<ChildProcess>(ffmpeg_arguments(options_, channels, output_.temporary()),
                                                     ChildOptions{.pipe_input = true, .errors = log_});
        } catch (const std::runtime_error& e) {
            throw std::runtime_error(std::string("video: ") + e.what() + " (Debian: apt-get install ffmpeg)");
        }
        // A pipe of a megabyte where the system allows it (Linux: the
        // default limit), not 64 KB: a 720p frame then goes in three writes
        // that ffmpeg takes as it can, not forty-odd turns of the two
        // processes. Where it is refused the frames go through all the same.
        ffmpeg_->set_pipe_size(1 << 20);
        writer_ = std::thread([this] { write_frames(); });
    }
    // Frame k, whole: queued for the writer (a copy, into the storage of a
    // frame written before: fresh storage for each frame came as fresh
    // pages, 2.7 MB a 720p frame). Returns the seconds spent waiting for
    // room in the queue.
    double write(const render::Image& frame, int k) {
        const auto start = Clock::now();
        Queued next{{}, k};
        {
            const std::lock_guard lock(mutex_);
            if (!spare_.empty()) next.pixels = std::move(spare_.back()), spare_.pop_back();
        }
        next.pixels.assign(frame.pixels.begin(), frame.pixels.end());  // copied outside the lock
        std::unique_lock lock(mutex_);
        room_.wait(lock, [&] { return queue_.size() + (writing_ ? 1 : 0) < kQueued || broken_at_ >= 0; });
        if (broken_at_ >= 0) {
            lock.unlock();
            broken();
        }
        queue_.push_back(std::move(next));
        lock.unlock();
        ready_.notify_one();
        return std::chrono::duration<double>(Clock::now() - start).count();
    }
    void finish() {
        stop_writer();
        if (broken_at_ >= 0) broken();
        const int status = ffmpeg_->wait();
        if (const int signal = child_interrupt(status); signal != 0) throw_interrupted("video", "the end", signal);
        check_interrupt("video", "the end");
        if (status != 0) {
            // ffmpeg's own words decide: a full disk is the output's error (exit 2), anything else ffmpeg's.
            const std::string said = read_all(log_);
            if (said.find("No space left") != std::string::npos || said.find("File too large") != std::string::npos)
                throw output_.error(said);
            throw std::runtime_error("video: ffmpeg failed (" + describe_status(status) + "): " + said);
        }
        if (!whole_video(output_.temporary(), options_.output.extension() == ".gif"))
            throw output_.error("the video ffmpeg wrote is cut short (the disk full, or a file size limit)");
        output_.commit();
    }

private:
    static constexpr std::size_t kQueued = 2;
    struct Queued {
        std::vector<std::uint8_t> pixels;
        int k = 0;
    };

    // The writer thread: frames in order, until told to stop and the queue is
    // empty, or a write fails (ffmpeg stopped reading).
    void write_frames() {
        for (;;) {
            std::unique_lock lock(mutex_);
            ready_.wait(lock, [&] { return !queue_.empty() || stopping_; });
            if (queue_.empty()) return;
            Queued next = std::move(queue_.front());
            queue_.pop_front();
            writing_ = true;
            lock.unlock();
            const bool ok = ffmpeg_->write(next.pixels.data(), next.pixels.size());
            lock.lock();
            writing_ = false;
            spare_.push_back(std::move(next.pixels));
            if (!ok) {
                broken_at_ = next.k;
                queue_.clear();
            }
            lock.unlock();
            room_.notify_one();
            if (!ok) return;
        }
    }
    void stop_writer() {
        if (!writer_.joinable()) return;
        {
            const std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        ready_.notify_one();
        writer_.join();
    }
    [[noreturn]] void broken() {
        // Ctrl+C in a terminal reaches ffmpeg too, which stops reading: say which.
        const std::string where = "frame " + std::to_string(broken_at_);
        check_interrupt("video", where);
        throw std::runtime_error("video: ffmpeg stopped reading frames (broken pipe) at " + where + ": " +
                                 read_all(log_));
    }

    const VideoOptions& options_;
    OutputFile output_;
    fs::path log_;
    std::unique_ptr<ChildProcess> ffmpeg_;
    std::thread writer_;
    std::mutex mutex_;
    std::condition_variable ready_, room_;  // a frame to write; room in the queue (or a failure)
    std::deque<Queued> queue_;
    std::vector<std::vector<std::uint8_t>> spare_;  // written frames' storage, for the next ones (at most kQueued + 1)
    bool stopping_ = false;
    bool writing_ = false;  // a frame taken from the queue is being written (it counts against kQueued)
    int broken_at_ = -1;    // the frame whose write failed
};

// The frames of one video, in order: physics up to each frame's time and the
// tiles' draw lists (on a thread of their own, a few frames ahead), the tiles
// drawn, the frame assembled and handed to the encoder. With one tile,
// frame k is drawn and its read queued, then frame k - 1 (drawn meanwhile by
// the renderer's threads) is taken and encoded; a grid of tiles reads each
// tile as it is drawn (the renderer redraws for each).
class FrameLoop {
public:
    FrameLoop(const SceneDef& scene, const VideoOptions& options, std::vector<std::unique_ptr<SceneRun>>& runs,
              const TileGrid& grid, const TileTexts& texts, render::Renderer& renderer, int frames)
        : scene_(scene),
          options_(options),
          runs_(runs),
          grid_(grid),
          texts_(texts),
          renderer_(renderer),
          frames_(frames),
          encoder_(options),
          progress_("video", options.progress, frames),
          settings_{.width = grid.tile_w, .height = grid.tile_h, .msaa_samples = 4} {}

    VideoStats run() {
        const bool behind = grid_.n == 1;
        {
            // The scenes step on a thread of their own: two frames' lists
            // waiting (and a third being made) cover a frame whose physics
            // takes longer than the next one's drawing, without holding more.
            Ahead<Scenes> ahead(
                frames_, 2, [] { sim::prepare_rigid_thread(); }, [this](int k) { return advance(k); });
            for (int k = 0; k < frames_; ++k) {
                draw(ahead.next(), behind);
                if (!behind) {
                    emit(k);
                } else if (k > 0) {
                    take(k - 1);
                }
            }
            if (behind) take(frames_ - 1);
        }
        encoder_.finish();
        VideoStats stats;
        stats.frames = frames_;
        stats.physics_ms = 1e3 * physics_ / frames_;
        stats.render_ms = 1e3 * render_ / frames_;
        stats.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
        stats.encode_ms = 1e3 * encode_ / frames_;
        stats.passes.add(passes_, 1.0 / frames_);
        stats.last_frame = runs_.front()->frame();
        stats.diverged_frame = runs_.front()->diverged_frame();
        return stats;
    }

private:
    // What frame k shows: each tile's draw list, its texts added.
    struct Scenes {
        std::vector<render::DrawList> lists;
        double physics = 0.0;  // s, stepping and building the lists
    };

    // Frame k's physics and draw lists (on the stepping thread).
    Scenes advance(int k) {
        const double t = static_cast<double>(k) / options_.fps;  // s, what this frame shows
        const auto start = Clock::now();
        for (auto& run : runs_) {
            const double dt = run->step().dt;
            while (run->time() + dt <= t + 1e-9 && run->advance()) {
            }
        }
        Scenes scenes;
        for (const auto& run : runs_) scenes.lists.push_back(run->draw_list(grid_.tile_w, grid_.tile_h));
        share_plot_ranges(scenes.lists);
        for (int i = 0; i < grid_.n; ++i) {
            texts_.add(scenes.lists[static_cast<std::size_t>(i)], options_, static_cast<std::size_t>(i), grid_.tile_h,
                       t);
        }
        scenes.physics = std::chrono::duration<double>(Clock::now() - start).count();
        return scenes;
    }

    // A frame's tiles: each drawn and its read queued (`behind`), or drawn,
    // read and put in the frame.
    void draw(const Scenes& scenes, bool behind) {
        const auto start = Clock::now();
        for (int i = 0; i < grid_.n; ++i) {
            const render::DrawList& list = scenes.lists[static_cast<std::size_t>(i)];
            renderer_.draw(list, settings_);
            renderer_.queue_read_back();
            if (!behind) {
                renderer_.take_read_back(tile_);
                place(tile_, i);
            }
            if (options_.verbose) passes_.add(renderer_.last_frame().passes);
        }
        physics_ += scenes.physics;
        render_ += std::chrono::duration<double>(Clock::now() - start).count();
    }

    // The oldest queued frame (the one tile), into the frame and to the encoder as frame k.
    void take(int k) {
        const auto start = Clock::now();
        renderer_.take_read_back(tile_);
        if (options_.verbose) passes_.read_back += renderer_.last_frame().passes.read_back;
        place(tile_, 0);
        render_ += std::chrono::duration<double>(Clock::now() - start).count();
        emit(k);
    }

    // Tile i into the frame. The first tile says the pixel format: the frame
    // around the tiles, the compare grid's title card, and ffmpeg started for it.
    void place(const render::Image& tile, int i) {
        if (!encoder_.started()) {
            frame_.width = options_.width;
            frame_.height = options_.height;
            frame_.channels = tile.channels;
            frame_.pixels.assign(static_cast<std::size_t>(frame_.width) * frame_.height * frame_.channels, 24);
            if (grid_.cols * grid_.rows > grid_.n) {  // the free cell after the last tile
                title_card(frame_, scene_, options_.compare, grid_.x(grid_.n), grid_.y(grid_.n), grid_.tile_w);
            }
            encoder_.start(frame_.channels);
        }
        blit(frame_, tile, grid_.x(i), grid_.y(i));
    }

    // Video frame k is complete: to the encoder.
    void emit(int k) {
        encode_ += encoder_.write(frame_, k);
        if (interrupt_signal() != 0) check_interrupt("video", "frame " + std::to_string(k));
        char what[64];
        std::snprintf(what, sizeof what, "frame %d, %.1f frames/s", k + 1,
                      (k + 1) / std::max(1e-9, std::chrono::duration<double>(Clock::now() - start_).count()));
        progress_.step(what);
    }

    const SceneDef& scene_;
    const VideoOptions& options_;
    std::vector<std::unique_ptr<SceneRun>>& runs_;
    const TileGrid& grid_;
    const TileTexts& texts_;
    render::Renderer& renderer_;
    const int frames_;
    Encoder encoder_;
    Progress progress_;
    const render::RenderSettings settings_;
    const Clock::time_point start_ = Clock::now();
    render::Image frame_;
    render::Image tile_;                  // each tile read back into the same storage, frame after frame
    render::Renderer::PassTimes passes_;  // ms, summed over the frames (options.verbose)
    double physics_ = 0.0, render_ = 0.0, encode_ = 0.0;  // s
};

}  // namespace

std::vector<std::string> ffmpeg_arguments(const VideoOptions& o, int channels, const fs::path& output) {
    std::vector<std::string> a = {"ffmpeg",
                                  "-y",
                                  "-nostdin",
                                  "-loglevel",
                                  "error",
                                  "-f",
                                  "rawvideo",
                                  "-pix_fmt",
                                  channels == 4 ? "rgba" : "rgb24",
                                  "-s",
                                  std::to_string(o.width) + "x" + std::to_string(o.height),
                                  "-r",
                                  std::to_string(o.fps),
                                  "-i",
                                  "-"};
    if (o.output.extension() == ".gif") {
        // One palette for the whole clip, then an ordered (Bayer) dither: no crawling noise between frames.
        a.insert(a.end(),
                 {"-vf", "split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse=dither=bayer:bayer_scale=3",
                  "-f", "gif"});
    } else {
        a.insert(a.end(),
                 {"-c:v",         "libx264",     "-preset",   "medium",           "-crf",  "20",         "-pix_fmt",
                  "yuv420p",      "-colorspace", "bt709",     "-color_primaries", "bt709", "-color_trc", "bt709",
                  "-color_range", "tv",          "-movflags", "+faststart",       "-f",    "mp4"});
    }
    a.push_back("file:" + output.string());  // "file:": a name with a colon or a leading '-' is still a file
    return a;
}

VideoStats write_video(const SceneDef& scene, const std::vector<Override>& overrides, const VideoOptions& options) {
    validate(options);
    const double seconds = options.seconds > 0.0 ? options.seconds : scene.frames * scene.step.dt;  // s simulated
    // The scene's own length is held to --seconds' limit too: a scene of
    // 1e7 frames of 10 s asked for 1.2e10 video frames, more than an int
    // holds, and came out as a video of one frame.
    if (seconds > kMaxVideoSeconds) {
        throw sim::InputError("video: " + scene.name + " runs " + sim::format_value(seconds) + " s (" +
                              std::to_string(scene.frames) + " frames of " + sim::format_value(scene.step.dt) +
                              " s); a video shows at most " + sim::format_value(kMaxVideoSeconds) +
                              " s: give --seconds");
    }
    const int frames = std::max(1, static_cast<int>(std::lround(seconds * options.fps)));
    const std::vector<std::unique_ptr<SceneDef>> defs = tile_scenes(scene, overrides, options);
    std::vector<std::unique_ptr<SceneRun>> runs;
    for (const auto& d : defs) runs.push_back(std::make_unique<SceneRun>(*d));
    const TileGrid grid = tile_grid(static_cast<int>(runs.size()), options);
    const TileTexts texts(scene, options, grid, seconds);

    const auto context =
        options.backend ? render::create_context({.backend = *options.backend}) : render::create_fastest_context();
    render::Renderer renderer(*context);
    renderer.time_passes(options.verbose);
    const InterruptScope interrupts;  // Ctrl+C: stop at the next frame, remove the temporary file
    FrameLoop loop(scene, options, runs, grid, texts, renderer, frames);
    VideoStats stats = loop.run();
    stats.renderer = context->fingerprint().summary();
    return stats;
}

}  // namespace scenes
