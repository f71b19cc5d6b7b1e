// check --junit: the check as JUnit XML, which CI systems (GitLab, Jenkins,
// GitHub's test reporters) read: one testcase per scene, its verdict line and
// evidence in a failure.
#include "scenes/check/check_report.h"
#include "scenes/common/output_file.h"

#include <cstdio>
#include <sstream>

namespace scenes {
namespace {

// Text for an XML attribute or element: the five entities escaped, and the
// control characters XML 1.0 cannot hold written as '?'.
std::string xml(const std::string& text) {
    std::string out;
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '&') {
            out += "&amp;";
        } else if (c == '<') {
            out += "&lt;";
        } else if (c == '>') {
            out += "&gt;";
        } else if (c == '"') {
            out += "&quot;";
        } else if (c == '\'') {
            out += "&apos;";
        } else if (u < 0x20 && c != '\t' && c != '\n' && c != '\r') {
            out += '?';
        } else {
            out += c;
        }
    }
    return out;
}

std::string seconds(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", s);
    return text;
}

// A failure's body: the verdict line, then where the evidence is.
std::string evidence(const SceneCheck& c, const std::filesystem::path& report) {
    std::string out = c.message + "\n";
    const std::pair<const char*, const std::string*> files[] = {{"side by side", &c.side_png},
                                                                {"expected", &c.expected_png},
                                                                {"actual", &c.actual_png},
                                                                {"diff", &c.diff_png},
                                                                {"the actual run", &c.actual_recording}};
    for (const auto& [what, path] : files) {
        if (!path->empty()) out += std::string(what) + ": " + (report / *path).string() + "\n";
    }
    out += "report: " + (report / "index.html").string() + "\n";
    return out;
}

}  // namespace

std::string junit_xml(const std::vector<SceneCheck>& scenes, const ShardInfo& shard,
                      const std::filesystem::path& report) {
    int failures = 0, errors = 0;
    double total = 0.0;
    for (const SceneCheck& c : scenes) {
        errors += c.status == SceneCheck::Status::error ? 1 : 0;
        failures += c.status == SceneCheck::Status::fail || c.status == SceneCheck::Status::missing ||
                    c.status == SceneCheck::Status::exploded;
        total += c.seconds;
    }
    const std::string suite = shard.count == 0 ? "plausible check"
                                               : "plausible check, shard " + std::to_string(shard.index) + " of " +
                                                     std::to_string(shard.count);
    std::ostringstream out;
    const std::string counts = "tests=\"" + std::to_string(scenes.size()) + "\" failures=\"" +
                               std::to_string(failures) + "\" errors=\"" + std::to_string(errors) + "\" time=\"" +
                               seconds(total) + "\"";
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<testsuites name=\"" << xml(suite) << "\" " << counts << ">\n"
        << "  <testsuite name=\"" << xml(suite) << "\" " << counts << " skipped=\"0\">\n";
    for (const SceneCheck& c : scenes) {
        out << "    <testcase classname=\"plausible.check\" name=\"" << xml(c.scene) << "\" time=\""
            << seconds(c.seconds) << "\"";
        const bool error = c.status == SceneCheck::Status::error;
        if (c.status == SceneCheck::Status::pass || c.status == SceneCheck::Status::updated) {
            out << "/>\n";
            continue;
        }
        const char* tag = error ? "error" : "failure";
        out << ">\n      <" << tag << " type=\"" << status_name(c.status) << "\" message=\"" << xml(c.message) << "\">"
            << xml(evidence(c, report)) << "</" << tag << ">\n    </testcase>\n";
    }
    out << "  </testsuite>\n</testsuites>\n";
    return out.str();
}

void write_junit(const std::filesystem::path& file, const std::vector<SceneCheck>& scenes, const ShardInfo& shard,
                 const std::filesystem::path& report) {
    write_output(file, junit_xml(scenes, shard, report));
}

}  // namespace scenes
