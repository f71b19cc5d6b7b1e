#include "scenes/check/check_report.h"
#include "scenes/common/output_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace scenes {
namespace {

namespace fs = std::filesystem;

bool failed(SceneCheck::Status s) {
    return s == SceneCheck::Status::fail || s == SceneCheck::Status::exploded || s == SceneCheck::Status::error ||
           s == SceneCheck::Status::missing;
}

std::string escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

nlohmann::json to_json(const SceneCheck& c) {
    nlohmann::json j = {
        {"scene", c.scene},
        {"status", status_name(c.status)},
        {"message", c.message},
        {"first_hash_mismatch", c.first_hash_mismatch},
        {"seconds", c.seconds},
        {"fingerprint_expected", c.fingerprint_expected},
        {"fingerprint_actual", c.fingerprint_actual},
        {"arch_expected", c.arch_expected},
        {"arch_actual", c.arch_actual},
        {"hashes_compared", c.hashes_comparable()},
        {"images",
         {{"expected", c.expected_png}, {"actual", c.actual_png}, {"diff", c.diff_png}, {"side", c.side_png}}}};
    nlohmann::json hashes = nlohmann::json::array();
    for (const CheckpointHash& h : c.hashes) {
        hashes.push_back(
            {{"frame", h.frame}, {"expected", h.expected}, {"actual", h.actual}, {"same", h.expected == h.actual}});
    }
    j["hashes"] = hashes;
    // Where the physics first changed (the golden's frame-by-frame hashes).
    if (c.changed_frame >= 0) {
        j["physics_change"] = {{"frame", c.changed_frame},
                               {"substep", c.changed_substep >= 0 ? nlohmann::json(c.changed_substep + 1) : nullptr},
                               {"substeps", c.substeps},
                               {"time", c.changed_time},
                               {"objects_frame", c.objects_frame >= 0 ? nlohmann::json(c.objects_frame) : nullptr},
                               {"objects", c.changed_objects}};
    } else {
        j["physics_change"] = nullptr;
    }
    if (!c.hashes_note.empty()) j["frame_hashes_note"] = c.hashes_note;
    j["actual_recording"] = c.actual_recording.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.actual_recording);
    if (c.image) {
        const render::GoldenDiff& d = *c.image;
        j["image"] = {{"identical", d.identical},
                      {"pass", d.pass},
                      {"size_mismatch", d.size_mismatch},
                      {"summary", d.summary},
                      {"small_pixels", d.small_pixels},
                      {"large_pixels", d.large_pixels},
                      {"small_share", d.small_share},
                      {"large_share", d.large_share},
                      {"max_d", d.max_d},
                      {"large_box", {d.large_box.x0, d.large_box.y0, d.large_box.x1, d.large_box.y1}}};
    } else {
        j["image"] = nullptr;
    }
    return j;
}

constexpr const char* kStyle = R"(
body { font: 14px/1.45 system-ui, sans-serif; margin: 24px; color: #222; background: #fafafa; }
h1 { font-size: 20px; margin: 0 0 8px; }
.counts span { display: inline-block; margin-right: 14px; padding: 2px 8px; border-radius: 4px; background: #eee; }
.scene { background: #fff; border: 1px solid #ddd; border-left: 6px solid #999; border-radius: 4px; margin: 14px 0; padding: 10px 14px; }
.scene.pass, .scene.updated { border-left-color: #2e9d48; }
.scene.fail, .scene.exploded, .scene.error { border-left-color: #d33; }
.scene.missing { border-left-color: #e0a000; }
.scene h2 { font-size: 16px; margin: 0 0 4px; }
.status { font-size: 12px; text-transform: uppercase; padding: 1px 6px; border-radius: 3px; color: #fff; background: #999; margin-left: 6px; }
.pass .status, .updated .status { background: #2e9d48; } .fail .status, .exploded .status, .error .status { background: #d33; }
.missing .status { background: #e0a000; }
.message { font-family: ui-monospace, monospace; white-space: pre-wrap; }
table { border-collapse: collapse; margin: 6px 0; font-family: ui-monospace, monospace; font-size: 12px; }
td, th { border: 1px solid #ddd; padding: 2px 6px; text-align: left; }
tr.differs td { background: #fde2e2; }
.images img { max-width: 100%; image-rendering: pixelated; border: 1px solid #ccc; margin: 4px 0; }
.flicker { cursor: pointer; }
.hint { font-size: 12px; color: #666; }
table.summary td { vertical-align: middle; } table.summary img { height: 48px; border: 1px solid #ccc; }
td.pass, td.updated { color: #2e9d48; } td.fail, td.exploded, td.error { color: #d33; } td.missing { color: #e0a000; }
)";

// Clicking a flicker image swaps it between expected and actual.
constexpr const char* kScript = R"(
document.querySelectorAll('img.flicker').forEach(function (img) {
  img.addEventListener('click', function () {
    var showing = img.getAttribute('data-showing') === 'expected' ? 'actual' : 'expected';
    img.src = img.getAttribute('data-' + showing);
    img.setAttribute('data-showing', showing);
    img.nextElementSibling.textContent = 'showing ' + showing + ' (click to flip)';
  });
});
)";

std::string scene_html(const SceneCheck& c) {
    std::ostringstream h;
    h << "<div class=\"scene " << status_name(c.status) << "\" id=\"" << escape(c.scene) << "\">\n<h2>"
      << escape(c.scene) << "<span class=\"status\">" << status_name(c.status)
      << "</span></h2>\n<div class=\"message\">" << escape(c.message) << "</div>\n";
    if (c.image) h << "<div>image: " << escape(c.image->summary) << "</div>\n";
    if (!c.actual_recording.empty()) {
        h << "<div>The actual run is kept as a recording, <a href=\"" << escape(c.actual_recording) << "\">"
          << escape(c.actual_recording) << "</a>: step and scrub through it frame by frame with <code>plausible view "
          << escape(c.actual_recording)
          << "</code>, run in this report's folder (a CI job's artifact: where you unpacked it), "
          << "or replay it with <code>plausible run</code> or <code>render</code>.</div>\n";
    }
    if (c.changed_frame >= 0) {
        h << "<table><tr><th>physics first changed at</th><th>substep</th><th>t (s)</th><th>objects that differ"
          << (c.objects_frame >= 0 ? " (at frame " + std::to_string(c.objects_frame) + ")" : "")
          << "</th></tr>\n<tr class=\"differs\"><td>frame " << c.changed_frame << "</td><td>"
          << (c.changed_substep >= 0 ? std::to_string(c.changed_substep + 1) + " of " + std::to_string(c.substeps)
                                     : "-")
          << "</td><td>" << c.changed_time << "</td><td>";
        for (std::size_t k = 0; k < c.changed_objects.size(); ++k) {
            h << (k == 0 ? "" : ", ") << escape(c.changed_objects[k]);
        }
        if (c.objects_frame >= 0 && c.changed_objects.empty()) h << "(no named object)";
        h << "</td></tr>\n</table>\n";
    }
    if (failed(c.status) && !c.hashes.empty()) {
        h << "<table><tr><th>checkpoint</th><th>frame</th><th>expected hash</th><th>actual hash</th></tr>\n";
        for (std::size_t i = 0; i < c.hashes.size(); ++i) {
            const CheckpointHash& x = c.hashes[i];
            h << "<tr" << (x.expected != x.actual ? " class=\"differs\"" : "") << "><td>" << i << "</td><td>" << x.frame
              << "</td><td>" << escape(x.expected.empty() ? "(none)" : x.expected) << "</td><td>" << escape(x.actual)
              << "</td></tr>\n";
        }
        h << "</table>\n";
    }
    if (!c.fingerprint_expected.empty() && c.fingerprint_expected != c.fingerprint_actual) {
        h << "<div>renderer of the golden: <code>" << escape(c.fingerprint_expected)
          << "</code><br>renderer now: <code>" << escape(c.fingerprint_actual) << "</code></div>\n";
    }
    if (!c.expected_png.empty() || !c.actual_png.empty()) {
        h << "<div class=\"images\">\n";
        if (!c.expected_png.empty() && !c.actual_png.empty()) {
            h << "<img class=\"flicker\" src=\"" << escape(c.actual_png) << "\" data-showing=\"actual\" data-actual=\""
              << escape(c.actual_png) << "\" data-expected=\"" << escape(c.expected_png)
              << "\" alt=\"actual\"><div class=\"hint\">showing actual (click to flip)</div>\n";
        } else {
            const std::string& only = c.actual_png.empty() ? c.expected_png : c.actual_png;
            h << "<img src=\"" << escape(only) << "\" alt=\"" << (c.actual_png.empty() ? "expected" : "actual")
              << "\">\n";
        }
        if (!c.diff_png.empty())
            h << "<div>diff (grey: same, yellow: small, red: large, blue: box of large errors)</div><img src=\""
              << escape(c.diff_png) << "\" alt=\"diff\">\n";
        if (!c.side_png.empty())
            h << "<div><a href=\"" << escape(c.side_png) << "\">expected | actual | diff side by side</a></div>\n";
        h << "</div>\n";
    }
    h << "</div>\n";
    return h.str();
}

// A share of the pixels as a percentage, "0.0123%".
std::string fmt_share(double share) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g%%", 100.0 * share);
    return text;
}

// One row a scene, failures first: its verdict, where the physics changed,
// its largest pixel error and a thumbnail; a scene with a card links to it.
std::string summary_html(const std::vector<const SceneCheck*>& order) {
    std::ostringstream h;
    h << "<table class=\"summary\"><tr><th>scene</th><th>verdict</th><th>physics changed at</th>"
         "<th>largest pixel error</th><th>actual</th></tr>\n";
    for (const SceneCheck* c : order) {
        const std::string name = escape(c->scene);
        h << "<tr><td>" << (c->status == SceneCheck::Status::pass ? name : "<a href=\"#" + name + "\">" + name + "</a>")
          << "</td><td class=\"" << status_name(c->status) << "\">" << status_name(c->status) << "</td><td>";
        if (c->changed_frame >= 0) {
            h << "frame " << c->changed_frame;
            if (c->changed_substep >= 0) h << ", substep " << c->changed_substep + 1 << " of " << c->substeps;
        } else {
            const bool same = !c->hashes.empty() && c->first_hash_mismatch < 0;
            h << (same ? "identical" : "-");
        }
        h << "</td><td>";
        if (!c->image) {
            h << "-";
        } else if (c->image->identical) {
            h << "identical";
        } else {
            h << escape(fmt_share(c->image->large_share)) << " of pixels large, max d " << c->image->max_d;
        }
        h << "</td><td>";
        if (!c->actual_png.empty()) h << "<img src=\"" << escape(c->actual_png) << "\" alt=\"actual\">";
        h << "</td></tr>\n";
    }
    h << "</table>\n";
    return h.str();
}

}  // namespace

const char* status_name(SceneCheck::Status status) {
    switch (status) {
        case SceneCheck::Status::pass:
            return "pass";
        case SceneCheck::Status::fail:
            return "fail";
        case SceneCheck::Status::missing:
            return "missing";
        case SceneCheck::Status::exploded:
            return "exploded";
        case SceneCheck::Status::updated:
            return "updated";
        case SceneCheck::Status::error:
            return "error";
    }
    return "?";
}

void write_check_report(const fs::path& dir, const std::vector<SceneCheck>& scenes, const ShardInfo& shard) {
    make_output_folder(dir);
    nlohmann::json report = {{"scenes", nlohmann::json::array()}};
    for (const SceneCheck& c : scenes) report["scenes"].push_back(to_json(c));
    const std::string shard_line =
        shard.count == 0 ? ""
                         : "shard " + std::to_string(shard.index) + " of " + std::to_string(shard.count) + ": " +
                               std::to_string(scenes.size()) + " of the " + std::to_string(shard.of) + " scenes";
    report["shard"] =
        shard.count == 0
            ? nlohmann::json(nullptr)
            : nlohmann::json{{"index", shard.index}, {"count", shard.count}, {"scenes_in_all_shards", shard.of}};

    int counts[6] = {};
    for (const SceneCheck& c : scenes) ++counts[static_cast<int>(c.status)];
    std::vector<const SceneCheck*> order;
    for (const SceneCheck& c : scenes) order.push_back(&c);
    std::stable_partition(order.begin(), order.end(), [](const SceneCheck* c) { return failed(c->status); });
    std::ostringstream html;
    html << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Plausible golden "
            "check</title><style>"
         << kStyle << "</style></head><body>\n<h1>Plausible golden check</h1>\n";
    if (!shard_line.empty()) html << "<div class=\"hint\">" << escape(shard_line) << "</div>\n";
    html << "<div class=\"counts\">";
    for (auto s : {SceneCheck::Status::pass, SceneCheck::Status::fail, SceneCheck::Status::exploded,
                   SceneCheck::Status::missing, SceneCheck::Status::error, SceneCheck::Status::updated}) {
        html << "<span>" << status_name(s) << ": " << counts[static_cast<int>(s)] << "</span>";
    }
    html << "</div>\n";
    html << summary_html(order);
    for (const SceneCheck* c : order) {
        if (c->status != SceneCheck::Status::pass) html << scene_html(*c);
    }
    html << "<script>" << kScript << "</script>\n</body></html>\n";
    write_output(dir / "report.json", report.dump(2) + "\n");
    write_output(dir / "index.html", html.str());
}

}  // namespace scenes
