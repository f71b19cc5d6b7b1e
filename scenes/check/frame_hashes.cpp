#include "scenes/check/frame_hashes.h"

#include "scenes/model/scene.h"

#include <algorithm>
#include <charconv>
#include <cinttypes>
#include <cstdio>
#include <sstream>

namespace scenes {
namespace {

constexpr int kVersion = 1;
constexpr std::string_view kMagic = "plausible-hashes";

std::string hex(std::uint64_t value, int digits) {
    char text[24];
    std::snprintf(text, sizeof text, "%0*" PRIx64, digits, value);
    return text;
}

// The line being read, for errors that name it.
struct Reader {
    const std::string& file;
    int line = 0;

    [[noreturn]] void fail(const std::string& what) const {
        throw SceneError(file + ":" + std::to_string(line) + ": " + what);
    }

    std::vector<std::string_view> words(std::string_view text) const {
        std::vector<std::string_view> out;
        std::size_t i = 0;
        while (i < text.size()) {
            while (i < text.size() && text[i] == ' ') ++i;
            const std::size_t start = i;
            while (i < text.size() && text[i] != ' ') ++i;
            if (i > start) out.push_back(text.substr(start, i - start));
        }
        return out;
    }

    // A whole number in [lo, hi].
    long long integer(std::string_view word, long long lo, long long hi, const char* what) const {
        long long value = 0;
        const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
        if (error != std::errc{} || end != word.data() + word.size() || value < lo || value > hi) {
            fail(std::string(what) + " must be a whole number in " + std::to_string(lo) + " .. " + std::to_string(hi) +
                 " (got \"" + std::string(word) + "\")");
        }
        return value;
    }

    // Exactly `digits` hex digits.
    std::uint64_t hex_value(std::string_view word, std::size_t digits, const char* what) const {
        std::uint64_t value = 0;
        const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value, 16);
        if (word.size() != digits || error != std::errc{} || end != word.data() + word.size()) {
            fail(std::string(what) + " must be " + std::to_string(digits) + " hex digits (got \"" + std::string(word) +
                 "\")");
        }
        return value;
    }
};

void read_frame(const Reader& r, const std::vector<std::string_view>& w, RunHashes& h) {
    const auto frame = r.integer(w[1], 0, 100'000'000, "the frame");
    if (frame != static_cast<long long>(h.frames.size())) {
        r.fail("frame " + std::to_string(frame) + " where frame " + std::to_string(h.frames.size()) +
               " was expected (one line per frame, in order)");
    }
    if (w.size() < 3) r.fail("frame " + std::to_string(frame) + " has no state hash");
    FrameRecord f;
    f.hash = r.hex_value(w[2], 16, "a state hash");
    const std::size_t substeps = frame == 0 ? 0 : static_cast<std::size_t>(h.substeps - 1);
    if (w.size() - 3 != substeps) {
        r.fail("frame " + std::to_string(frame) + " has " + std::to_string(w.size() - 3) + " substep hashes, " +
               std::to_string(substeps) + " expected (substeps " + std::to_string(h.substeps) + ", less the last)");
    }
    for (std::size_t k = 3; k < w.size(); ++k) {
        f.substeps.push_back(static_cast<std::uint16_t>(r.hex_value(w[k], 4, "a substep hash")));
    }
    h.frames.push_back(std::move(f));
}

void read_objects(const Reader& r, const std::vector<std::string_view>& w, RunHashes& h) {
    const auto frame = static_cast<int>(r.integer(w[1], 0, 100'000'000, "the frame"));
    if (frame >= static_cast<int>(h.frames.size()))
        r.fail("object hashes of frame " + std::to_string(frame) + " before that frame's line");
    if (w.size() - 2 != h.objects.size()) {
        r.fail(std::to_string(w.size() - 2) + " object hashes for " + std::to_string(h.objects.size()) + " objects");
    }
    std::vector<std::uint32_t>& hashes = h.object_hashes[frame];
    hashes.clear();
    for (std::size_t k = 2; k < w.size(); ++k) {
        hashes.push_back(static_cast<std::uint32_t>(r.hex_value(w[k], 8, "an object hash")));
    }
}

}  // namespace

bool object_grid_frame(int frame, const std::vector<int>& checkpoints) {
    if (frame == 0 || (frame > 0 && (frame & (frame - 1)) == 0)) return true;
    return std::find(checkpoints.begin(), checkpoints.end(), frame) != checkpoints.end();
}

std::string format_run_hashes(const RunHashes& h) {
    std::ostringstream out;
    out << kMagic << ' ' << kVersion << "\nsubsteps " << h.substeps << '\n';
    for (const std::string& name : h.objects) out << "object " << name << '\n';
    for (std::size_t f = 0; f < h.frames.size(); ++f) {
        out << "frame " << f << ' ' << hex(h.frames[f].hash, 16);
        for (const std::uint16_t s : h.frames[f].substeps) out << ' ' << hex(s, 4);
        out << '\n';
        const auto objects = h.object_hashes.find(static_cast<int>(f));
        if (objects == h.object_hashes.end()) continue;
        out << "objects " << f;
        for (const std::uint32_t o : objects->second) out << ' ' << hex(o, 8);
        out << '\n';
    }
    return out.str();
}

RunHashes parse_run_hashes(std::string_view text, const std::string& file) {
    RunHashes h;
    Reader r{file};
    bool header = false, substeps = false;
    for (std::size_t start = 0; start < text.size();) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        const std::string_view line = text.substr(start, end - start);
        start = end + 1;
        ++r.line;
        if (line.find('\0') != std::string_view::npos) r.fail("not a text file (a NUL byte)");
        const std::vector<std::string_view> w = r.words(line);
        if (w.empty()) continue;
        if (!header) {
            if (w[0] != kMagic || w.size() != 2)
                r.fail("not a hashes file: the first line must be \"plausible-hashes 1\"");
            const auto version = r.integer(w[1], 0, 1'000'000, "the format version");
            if (version != kVersion) {
                r.fail("format version " + std::to_string(version) + ", and this build reads version " +
                       std::to_string(kVersion));
            }
            header = true;
        } else if (w[0] == "substeps" && w.size() == 2 && !substeps && h.frames.empty()) {
            h.substeps = static_cast<int>(r.integer(w[1], 1, 100'000, "substeps"));
            substeps = true;
        } else if (w[0] == "object" && h.frames.empty()) {
            h.objects.emplace_back(line.substr(line.find("object") + 7));
        } else if (w[0] == "frame" && w.size() >= 2 && substeps) {
            read_frame(r, w, h);
        } else if (w[0] == "objects" && w.size() >= 2) {
            read_objects(r, w, h);
        } else {
            r.fail("unexpected line \"" + std::string(line.substr(0, 60)) + "\"");
        }
    }
    r.line = std::max(r.line, 1);
    if (!header) r.fail("empty: not a hashes file");
    if (h.frames.empty()) r.fail("no frame lines");
    return h;
}

namespace {

// The objects that differ at `frame` (both runs keep it), by name.
std::vector<std::string> changed_objects(const RunHashes& expected, const RunHashes& actual, int frame) {
    const std::vector<std::uint32_t>& e = expected.object_hashes.at(frame);
    const std::vector<std::uint32_t>& a = actual.object_hashes.at(frame);
    std::vector<std::string> changed;
    for (std::size_t k = 0; k < actual.objects.size() && k < a.size(); ++k) {
        const auto found = std::find(expected.objects.begin(), expected.objects.end(), actual.objects[k]);
        if (found == expected.objects.end()) {
            changed.push_back(actual.objects[k] + " (new)");
            continue;
        }
        const auto j = static_cast<std::size_t>(found - expected.objects.begin());
        if (j < e.size() && e[j] != a[k]) changed.push_back(actual.objects[k]);
    }
    for (const std::string& name : expected.objects) {
        if (std::find(actual.objects.begin(), actual.objects.end(), name) == actual.objects.end()) {
            changed.push_back(name + " (gone)");
        }
    }
    return changed;
}

}  // namespace

HashChange locate_change(const RunHashes& expected, const RunHashes& actual) {
    HashChange c;
    const std::size_t common = std::min(expected.frames.size(), actual.frames.size());
    std::size_t f = 0;
    while (f < common && expected.frames[f].hash == actual.frames[f].hash) ++f;
    if (f == common && expected.frames.size() == actual.frames.size()) return c;
    c.frame = static_cast<int>(f);
    c.ended = f == common;
    if (f > 0 && f < common && expected.substeps == actual.substeps) {
        const std::vector<std::uint16_t>&e = expected.frames[f].substeps, &a = actual.frames[f].substeps;
        std::size_t k = 0;
        while (k < e.size() && k < a.size() && e[k] == a[k]) ++k;
        c.substep = static_cast<int>(k);  // all the short ones equal: the last substep, the frame's own
    }
    for (const auto& [frame, hashes] : actual.object_hashes) {
        if (frame < c.frame || expected.object_hashes.count(frame) == 0) continue;
        c.objects_frame = frame;
        c.objects = changed_objects(expected, actual, frame);
        break;
    }
    return c;
}

std::vector<std::string> group_changed(const std::vector<std::string>& changed,
                                       const std::vector<SceneObject>& objects) {
    auto is_changed = [&](const std::string& name) {
        return std::find(changed.begin(), changed.end(), name) != changed.end();
    };
    std::vector<std::string> out;
    for (std::size_t k = 0; k < objects.size();) {
        const std::string& group = objects[k].group;
        std::size_t end = k + 1;
        while (!group.empty() && end < objects.size() && objects[end].group == group) ++end;
        std::size_t count = 0;
        for (std::size_t j = k; j < end; ++j) count += is_changed(objects[j].name) ? 1 : 0;
        if (end - k > 1 && count == end - k) {
            out.push_back(group + " (all " + std::to_string(count) + " bodies)");
        } else {
            for (std::size_t j = k; j < end; ++j) {
                if (is_changed(objects[j].name)) out.push_back(objects[j].name);
            }
        }
        k = end;
    }
    // What the scene no longer has, or has anew, last.
    for (const std::string& name : changed) {
        if (name.ends_with(" (new)") || name.ends_with(" (gone)")) out.push_back(name);
    }
    return out;
}

}  // namespace scenes
