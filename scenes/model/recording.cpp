// Recordings: the file format (recording.h; docs/design.md "Recordings"),
// written and read byte by byte in little-endian order, and the scene a
// recording replays.
#include "scenes/model/recording.h"

#include "scenes/common/output_file.h"

#include "sim/integrators.h"
#include "sim/state_hash.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace scenes {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'P', 'L', 'S', 'B', 'L', 'R', 'E', 'C'};
constexpr std::uint32_t kByteOrder = 0x01020304;
// Sizes a sound file stays within (a count beyond them is corruption, not a
// reason to allocate).
constexpr std::uint64_t kMaxCount = 1ull << 32;

// --- writing -------------------------------------------------------------------------------

class Writer {
public:
    void u8(std::uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
    void u32(std::uint32_t v) {
        for (int k = 0; k < 4; ++k) u8(static_cast<std::uint8_t>(v >> (8 * k)));
    }
    void u64(std::uint64_t v) {
        for (int k = 0; k < 8; ++k) u8(static_cast<std::uint8_t>(v >> (8 * k)));
    }
    void i32(int v) { u32(static_cast<std::uint32_t>(v)); }
    void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
    void raw(std::string_view b) { bytes_ += b; }
    void text(const std::string& s) {
        u32(static_cast<std::uint32_t>(s.size()));
        bytes_ += s;
    }
    void doubles(const double* p, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) f64(p[i]);
    }
    void vec3s(const sim::Vec3Array& a) {
        u64(a.size());
        for (const double* c : a.span().c) doubles(c, a.size());  // all x, then all y, then all z
    }
    void vec(const Eigen::Vector3d& v) { doubles(v.data(), 3); }
    void quat(const Eigen::Quaterniond& q) { f64(q.w()), f64(q.x()), f64(q.y()), f64(q.z()); }
    // A section: its tag, then its payload's length and the payload.
    void section(const char (&tag)[5], const Writer& payload) {
        bytes_.append(tag, 4);
        u64(payload.bytes_.size());
        bytes_ += payload.bytes_;
    }
    const std::string& bytes() const { return bytes_; }

private:
    std::string bytes_;
};

void put_verdict(Writer& w, const sim::Verdict& v) {
    w.u8(v.exploded() ? 1 : 0);
    w.u64(v.frame);
    w.text(v.quantity);
    w.text(v.subject);
    w.u64(v.index);
    w.f64(v.value), w.f64(v.limit), w.f64(v.initial_energy);
}

void put_snapshot(Writer& w, const sim::World::Snapshot& s) {
    w.f64(s.state.t);
    w.vec3s(s.state.x);
    w.vec3s(s.state.v);
    w.u64(s.state.mass.size());
    w.doubles(s.state.mass.data(), s.state.mass.size());
    w.doubles(s.state.inv_mass.data(), s.state.inv_mass.size());
    w.vec3s(s.memory_a);
    w.vec3s(s.memory_x_prev);
    w.u8(s.memory_valid ? 1 : 0);
    w.text(std::string(sim::integrator_info(s.memory_integrator).name));
    w.f64(s.memory_h);
    w.u64(s.steps), w.u64(s.frames);
    w.f64(s.initial_energy);
    put_verdict(w, s.verdict);
    w.u64(s.plastic_rest.size());
    w.doubles(s.plastic_rest.data(), s.plastic_rest.size());
    w.u64(s.contained.size());
    for (const auto& c : s.contained) w.text(c.name), put_verdict(w, c.verdict);
    w.u64(s.bodies.size());
    for (const sim::BodyState& b : s.bodies) {
        w.vec(b.position), w.quat(b.orientation), w.vec(b.velocity), w.vec(b.angular_velocity);
        w.u8(b.awake ? 1 : 0);
        w.u32(b.idle_steps);
        w.f64(b.sleep_energy);
        w.vec(b.rest_position), w.quat(b.rest_orientation);
    }
    w.u64(s.rigid_steps);
}

// --- reading -------------------------------------------------------------------------------

// Reads one payload; every read is checked against its end.
class Reader {
public:
    Reader(const std::string& file, std::string_view bytes, std::size_t base, std::string what)
        : file_(file), bytes_(bytes), base_(base), what_(std::move(what)) {}

    [[noreturn]] void fail(const std::string& why) const {
        throw sim::InputError(file_ + ": not a readable recording: " + why + " (" + what_ + ", byte " +
                              std::to_string(base_ + pos_) + ")");
    }
    std::string_view take(std::size_t n) {
        if (n > bytes_.size() - pos_) fail("it ends early (truncated?)");
        const std::string_view out = bytes_.substr(pos_, n);
        pos_ += n;
        return out;
    }
    std::uint8_t u8() { return static_cast<std::uint8_t>(take(1)[0]); }
    std::uint32_t u32() {
        const std::string_view b = take(4);
        std::uint32_t v = 0;
        for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<std::uint8_t>(b[static_cast<std::size_t>(k)]);
        return v;
    }
    std::uint64_t u64() {
        const std::string_view b = take(8);
        std::uint64_t v = 0;
        for (int k = 7; k >= 0; --k) v = (v << 8) | static_cast<std::uint8_t>(b[static_cast<std::size_t>(k)]);
        return v;
    }
    int i32() { return static_cast<int>(u32()); }
    double f64() { return std::bit_cast<double>(u64()); }
    // A count of items of at least `each` bytes that follow (so that it is
    // never a reason to allocate more than the file holds).
    std::size_t count(std::size_t each = 1) {
        const std::uint64_t n = u64();
        if (n > kMaxCount || n > (bytes_.size() - pos_) / each) {
            fail("a count of " + std::to_string(n) + " is more than it holds");
        }
        return static_cast<std::size_t>(n);
    }
    std::string text() {
        const std::uint32_t n = u32();
        return std::string(take(n));
    }
    void doubles(double* p, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) p[i] = f64();
    }
    sim::Vec3Array vec3s() {
        sim::Vec3Array a(count(3 * sizeof(double)));
        for (double* c : a.span().c) doubles(c, a.size());
        return a;
    }
    Eigen::Vector3d vec() {
        Eigen::Vector3d v;
        doubles(v.data(), 3);
        return v;
    }
    Eigen::Quaterniond quat() {
        const double w = f64(), x = f64(), y = f64(), z = f64();
        return Eigen::Quaterniond(w, x, y, z);
    }
    bool done() const { return pos_ == bytes_.size(); }

private:
    const std::string& file_;
    std::string_view bytes_;
    std::size_t base_;  // where the payload starts in the file
    std::string what_;
    std::size_t pos_ = 0;
};

sim::Verdict get_verdict(Reader& r) {
    sim::Verdict v;
    v.status = r.u8() != 0 ? sim::Verdict::Status::exploded : sim::Verdict::Status::ok;
    v.frame = r.u64();
    v.quantity = r.text();
    v.subject = r.text();
    v.index = r.u64();
    v.value = r.f64(), v.limit = r.f64(), v.initial_energy = r.f64();
    return v;
}

sim::Integrator integrator_named(Reader& r) {
    const std::string name = r.text();
    const auto id = sim::integrator_from_name(name);
    if (!id) r.fail("no integrator '" + name + "' in this build");
    return *id;
}

sim::World::Snapshot get_snapshot(Reader& r) {
    sim::World::Snapshot s;
    s.state.t = r.f64();
    s.state.x = r.vec3s();
    s.state.v = r.vec3s();
    const std::size_t n = r.count();
    if (n != s.state.x.size() || n != s.state.v.size()) r.fail("its particle arrays differ in length");
    s.state.mass.resize(n), s.state.inv_mass.resize(n);
    r.doubles(s.state.mass.data(), n);
    r.doubles(s.state.inv_mass.data(), n);
    s.memory_a = r.vec3s();
    s.memory_x_prev = r.vec3s();
    s.memory_valid = r.u8() != 0;
    s.memory_integrator = integrator_named(r);
    s.memory_h = r.f64();
    s.steps = r.u64(), s.frames = r.u64();
    s.initial_energy = r.f64();
    s.verdict = get_verdict(r);
    s.plastic_rest.resize(r.count(sizeof(double)));
    r.doubles(s.plastic_rest.data(), s.plastic_rest.size());
    for (std::size_t k = r.count(); k > 0; --k) {
        sim::World::Contained c;
        c.name = r.text();
        c.verdict = get_verdict(r);
        s.contained.push_back(std::move(c));
    }
    for (std::size_t k = r.count(); k > 0; --k) {
        sim::BodyState b;
        b.position = r.vec(), b.orientation = r.quat(), b.velocity = r.vec(), b.angular_velocity = r.vec();
        b.awake = r.u8() != 0;
        b.idle_steps = r.u32();
        b.sleep_energy = r.f64();
        b.rest_position = r.vec(), b.rest_orientation = r.quat();
        s.bodies.push_back(b);
    }
    s.rigid_steps = r.u64();
    return s;
}

std::uint64_t fnv(std::string_view bytes) {
    sim::Fnv1a h;
    h.add(bytes.data(), bytes.size());
    return h.value();
}

}  // namespace

int recording_interval(int frames, std::size_t state_bytes) {
    const std::size_t fit = std::max<std::size_t>(1, kRecordingStatesBytes / std::max<std::size_t>(state_bytes, 1));
    // K = ceil((frames + 1) / fit): the multiples of K up to `frames` are at most `fit`.
    const std::uint64_t k = (static_cast<std::uint64_t>(std::max(frames, 0)) + fit) / fit;
    return static_cast<int>(std::max<std::uint64_t>(k, 1));
}

std::size_t snapshot_bytes(const sim::World::Snapshot& snapshot) {
    Writer w;
    put_snapshot(w, snapshot);
    return 4 + 8 + 4 + w.bytes().size();  // tag, length, frame, snapshot
}

std::uint64_t snapshot_hash(const sim::World::Snapshot& s, bool rigid) {
    const std::uint64_t particles = sim::state_hash(s.state);
    if (!rigid) return particles;
    // RigidWorld::hash's order: position, linear and angular velocity, then the quaternion w, x, y, z.
    sim::Fnv1a h;
    for (const sim::BodyState& b : s.bodies) {
        for (const Eigen::Vector3d* v : {&b.position, &b.velocity, &b.angular_velocity}) {
            for (int k = 0; k < 3; ++k) h.add((*v)[k]);
        }
        h.add(b.orientation.w()), h.add(b.orientation.x()), h.add(b.orientation.y()), h.add(b.orientation.z());
    }
    return sim::fold_hashes(particles, h.value());
}

namespace {

Writer serialize(const Recording& rec) {
    Writer out;
    out.raw(std::string_view(kMagic, sizeof kMagic));
    out.u32(Recording::kVersion);
    out.u32(kByteOrder);
    Writer scene;
    scene.text(rec.scene_name), scene.text(rec.scene_file), scene.text(rec.scene_text);
    scene.u32(static_cast<std::uint32_t>(rec.overrides.size()));
    for (const Override& o : rec.overrides) scene.text(o.key), scene.text(o.value);
    out.section("SCNE", scene);
    Writer step;
    step.text(std::string(sim::integrator_info(rec.step.integrator).name));
    step.f64(rec.step.dt), step.i32(rec.step.substeps), step.i32(rec.frames), step.i32(rec.every);
    out.section("STEP", step);
    Writer hashes;
    for (const std::uint64_t h : rec.hashes) hashes.u64(h);
    out.section("HASH", hashes);
    for (const auto& [frame, snapshot] : rec.states) {
        Writer state;
        state.i32(frame);
        put_snapshot(state, snapshot);
        out.section("STAT", state);
    }
    Writer end;
    end.u64(fnv(out.bytes()));
    out.section("END ", end);
    return out;
}

std::string mebibytes(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
    return text;
}

}  // namespace

std::uint64_t recording_bytes_without_states(const Recording& recording, int frames) {
    Recording bare = recording;
    bare.hashes.clear(), bare.states.clear();
    return serialize(bare).bytes().size() + 8 * (static_cast<std::uint64_t>(std::max(frames, 0)) + 1);
}

void write_recording(const fs::path& file, const Recording& rec) {
    const Writer out = serialize(rec);
    if (out.bytes().size() > kMaxRecordingBytes) {
        throw sim::InputError("--record: " + file.string() + " would take " + mebibytes(out.bytes().size()) +
                              ", more than a recording may (" + mebibytes(kMaxRecordingBytes) + ")");
    }
    write_output(file, std::string_view(out.bytes().data(), out.bytes().size()));
}

namespace {

// A file descriptor, closed when it goes.
struct OpenFile {
    int fd = -1;
    std::uint64_t size = 0;  // bytes, when it was opened
    OpenFile() = default;
    OpenFile(const OpenFile&) = delete;
    OpenFile& operator=(const OpenFile&) = delete;
    ~OpenFile() {
        if (fd >= 0) ::close(fd);
    }
};

// Opens a regular file for reading; O_NONBLOCK so that a FIFO with no writer
// is refused, not waited on. Empty message: opened.
std::string open_regular(const fs::path& path, OpenFile& f) {
    f.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (f.fd < 0) return std::string("cannot read the recording (") + std::strerror(errno) + ")";
    struct stat st {};
    if (::fstat(f.fd, &st) != 0) return std::string("cannot read the recording (") + std::strerror(errno) + ")";
    if (!S_ISREG(st.st_mode)) return "not a regular file (a recording is a file `run --record` wrote)";
    f.size = static_cast<std::uint64_t>(st.st_size);
    return {};
}

// Reads up to `n` bytes onto the end of `out`; fewer only at the file's end.
void read_some(const OpenFile& f, std::string& out, std::size_t n, const std::string& file) {
    const std::size_t start = out.size();
    out.resize(start + n);
    std::size_t got = 0;
    while (got < n) {
        const ssize_t r = ::read(f.fd, out.data() + start + got, n - got);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) throw sim::InputError(file + ": cannot read the recording (" + std::strerror(errno) + ")");
        if (r == 0) break;
        got += static_cast<std::size_t>(r);
    }
    out.resize(start + got);
}

// The magic, the version and the byte order (the first 16 bytes).
void check_header(std::string_view bytes, const std::string& file) {
    Reader head(file, bytes, 0, "its header");
    if (head.take(8) != std::string_view(kMagic, 8)) {
        throw sim::InputError(file +
                              ": not a recording (it does not start with PLSBLREC; `plausible run SCENE "
                              "--record FILE` makes one)");
    }
    const std::uint32_t version = head.u32();
    if (version != Recording::kVersion) {
        throw sim::InputError(file + ": a recording of format version " + std::to_string(version) +
                              ", and this build reads version " + std::to_string(Recording::kVersion));
    }
    if (head.u32() != kByteOrder) head.fail("its byte-order mark is wrong");
}

constexpr std::size_t kHeaderBytes = 16;

}  // namespace

bool is_recording(const fs::path& file) {
    OpenFile f;
    if (!open_regular(file, f).empty()) return false;
    std::string head;
    read_some(f, head, sizeof kMagic, file.string());
    return head == std::string_view(kMagic, sizeof kMagic);
}

Recording read_recording(const fs::path& path) {
    const std::string file = path.string();
    OpenFile f;
    if (const std::string why = open_regular(path, f); !why.empty()) throw sim::InputError(file + ": " + why);
    std::string bytes;
    read_some(f, bytes, kHeaderBytes, file);
    check_header(bytes, file);
    if (f.size > kMaxRecordingBytes) {
        throw sim::InputError(file + ": " + std::to_string(f.size) + " bytes is too large for a recording (at most " +
                              mebibytes(kMaxRecordingBytes) + ")");
    }
    if (f.size > bytes.size()) read_some(f, bytes, static_cast<std::size_t>(f.size - bytes.size()), file);
    return parse_recording(bytes, file);
}

Recording parse_recording(std::string_view bytes, const std::string& file) {
    check_header(bytes, file);
    Recording rec;
    bool scene = false, step = false, hashes = false;
    std::vector<std::size_t> state_at;  // where each STAT section starts
    for (std::size_t pos = kHeaderBytes;;) {
        Reader section(file, bytes.substr(pos), pos, "a section's header");
        const std::string tag(section.take(4));
        const std::size_t length = section.count();
        const std::size_t start = pos + 12;
        Reader r(file, bytes.substr(start, length), start, "section " + tag);
        if (tag == "END ") {
            if (r.u64() != fnv(bytes.substr(0, pos))) r.fail("its checksum differs (corrupted?)");
            if (start + length != bytes.size()) r.fail("bytes follow its end");
            break;
        }
        if (tag == "SCNE") {
            rec.scene_name = r.text(), rec.scene_file = r.text(), rec.scene_text = r.text();
            for (std::uint32_t k = r.u32(); k > 0; --k) {
                Override o;
                o.key = r.text(), o.value = r.text();
                rec.overrides.push_back(std::move(o));
            }
            scene = true;
        } else if (tag == "STEP") {
            rec.step.integrator = integrator_named(r);
            rec.step.dt = r.f64(), rec.step.substeps = r.i32(), rec.frames = r.i32(), rec.every = r.i32();
            if (rec.frames < 0 || rec.every < 1) r.fail("frames or K out of range");
            step = true;
        } else if (tag == "HASH") {
            rec.hashes.reserve(length / 8);
            while (!r.done()) rec.hashes.push_back(r.u64());
            hashes = true;
        } else if (tag == "STAT") {
            const int frame = r.i32();
            rec.states.emplace_back(frame, get_snapshot(r));
            state_at.push_back(pos);
        } else {
            r.fail("an unknown section '" + tag + "'");
        }
        if (!r.done()) r.fail("bytes left over at its end");
        pos = start + length;
    }
    Reader whole(file, bytes, 0, "the whole file");
    if (!scene || !step || !hashes) whole.fail("a section is missing (SCNE, STEP and HASH are required)");
    if (rec.hashes.size() != static_cast<std::size_t>(rec.frames) + 1) {
        whole.fail(std::to_string(rec.hashes.size()) + " frame hashes for " + std::to_string(rec.frames) + " frames");
    }
    // Each stored state against its frame's recorded hash: the viewer's seek
    // starts from one, so an edited one must not read as the recorded run.
    for (std::size_t k = 0; k < rec.states.size(); ++k) {
        const auto& [frame, state] = rec.states[k];
        Reader at(file, bytes.substr(state_at[k]), state_at[k], "section STAT of frame " + std::to_string(frame));
        if (frame < 0 || frame > rec.frames || (k > 0 && frame <= rec.states[k - 1].first)) {
            at.fail("its frame is out of order or beyond the " + std::to_string(rec.frames) + " recorded");
        }
        const std::uint64_t want = rec.hashes[static_cast<std::size_t>(frame)];
        // No bodies: the World may still have a rigid world (its bodies removed), whose hash is folded in.
        const bool same = snapshot_hash(state, !state.bodies.empty()) == want ||
                          (state.bodies.empty() && snapshot_hash(state, true) == want);
        if (!same) at.fail("the stored state is not the one the frame's recorded state hash says (edited?)");
    }
    return rec;
}

SceneDef scene_of(const Recording& rec, const fs::path& file) {
    SceneDef scene =
        parse_scene(rec.scene_text, file.string() + " (the recorded " + rec.scene_name + ")", rec.overrides);
    scene.name = rec.scene_name;
    scene.file = rec.scene_file;
    scene.text = rec.scene_text;
    scene.overrides = rec.overrides;
    if (scene.step.integrator != rec.step.integrator || scene.step.dt != rec.step.dt ||
        scene.step.substeps != rec.step.substeps) {
        throw sim::InputError(file.string() + ": its scene does not build the step settings it recorded");
    }
    auto run = std::make_shared<RecordedRun>();
    run->file = file;
    run->hashes = rec.hashes;
    run->every = rec.every;
    run->states = rec.states;
    scene.recorded = std::move(run);
    return scene;
}

SceneDef load_scene_or_recording(const std::string& name_or_path, const std::vector<Override>& overrides) {
    const bool recording =
        name_or_path.ends_with(".rec") ||
        (!name_or_path.ends_with(".toml") && fs::is_regular_file(name_or_path) && is_recording(name_or_path));
    if (recording) {
        if (!overrides.empty()) {
            throw sim::InputError(name_or_path +
                                  ": a recording replays the scene it ran; --set and the step options would "
                                  "change it (drop them, or record again with them)");
        }
        return scene_of(read_recording(name_or_path), name_or_path);
    }
    return load_scene(resolve_scene(name_or_path), overrides);
}

}  // namespace scenes
