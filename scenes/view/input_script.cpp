#include "scenes/view/input_script.h"

#include "sim/error.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace scenes::view {
namespace {

// The keys a script may press, by name (GLFW's codes).
int key_code(const std::string& name) {
    if (name.size() == 1 && name[0] >= 'a' && name[0] <= 'z') return GLFW_KEY_A + (name[0] - 'a');
    if (name.size() == 1 && name[0] >= '0' && name[0] <= '9') return GLFW_KEY_0 + (name[0] - '0');
    static const std::map<std::string, int> named = {{"space", GLFW_KEY_SPACE},
                                                     {"Return", GLFW_KEY_ENTER},
                                                     {"Right", GLFW_KEY_RIGHT},
                                                     {"Left", GLFW_KEY_LEFT},
                                                     {"Up", GLFW_KEY_UP},
                                                     {"Down", GLFW_KEY_DOWN},
                                                     {"Escape", GLFW_KEY_ESCAPE},
                                                     {"BackSpace", GLFW_KEY_BACKSPACE},
                                                     {"Tab", GLFW_KEY_TAB},
                                                     {"period", GLFW_KEY_PERIOD},
                                                     {"comma", GLFW_KEY_COMMA},
                                                     {"bracketleft", GLFW_KEY_LEFT_BRACKET},
                                                     {"bracketright", GLFW_KEY_RIGHT_BRACKET}};
    const auto it = named.find(name);
    return it == named.end() ? -1 : it->second;
}

int button_code(const std::string& name) {
    if (name == "left") return GLFW_MOUSE_BUTTON_LEFT;
    if (name == "right") return GLFW_MOUSE_BUTTON_RIGHT;
    if (name == "middle") return GLFW_MOUSE_BUTTON_MIDDLE;
    return -1;
}

// A finite number, the whole word (from_chars takes "nan" and "inf").
bool number(const std::string& word, double& value) {
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    return error == std::errc{} && end == word.data() + word.size() && std::isfinite(value);
}

}  // namespace

std::vector<InputEvent> read_input_script(const std::filesystem::path& file) {
    // Checked by stat before opening: a FIFO would block the open, a device never end.
    constexpr std::uintmax_t kMaxBytes = 16u << 20;  // as a scene file
    std::error_code error;
    const auto status = std::filesystem::status(file, error);
    if (!error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
        throw sim::InputError("view: --input " + file.string() + ": not a regular file");
    }
    if (const auto size = std::filesystem::file_size(file, error); !error && size > kMaxBytes) {
        throw sim::InputError("view: --input " + file.string() + ": " + std::to_string(size) +
                              " bytes is too large for an input script (at most 16 MiB)");
    }
    std::ifstream in(file);
    if (!in) throw sim::InputError("view: --input " + file.string() + ": cannot read it");
    return parse_input_script(in, file.string());
}

std::vector<InputEvent> parse_input_script(std::istream& in, const std::string& file) {
    std::vector<InputEvent> events;
    std::string line;
    for (int number_of_line = 1; std::getline(in, line); ++number_of_line) {
        const std::string where = file + ":" + std::to_string(number_of_line);
        auto fail = [&](const std::string& what) { throw sim::InputError(where + ": " + what); };
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream words(line);
        std::string frame_word, verb;
        if (!(words >> frame_word)) continue;  // blank or a comment
        InputEvent e;
        e.where = where;
        double frame = 0;
        if (!number(frame_word, frame) || frame < 1 || frame > 1e7 || frame != static_cast<int>(frame)) {
            fail("a line starts with the frame it happens at, a whole number from 1 (got '" + frame_word + "')");
        }
        e.frame = static_cast<int>(frame);
        if (!events.empty() && e.frame < events.back().frame) {
            fail("frame " + frame_word + " comes after frame " + std::to_string(events.back().frame) +
                 ": frames must not decrease");
        }
        if (!(words >> verb)) fail("frame " + frame_word + " has no event (key, text, move, press or release)");
        std::string rest;
        std::getline(words >> std::ws, rest);
        while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\r')) rest.pop_back();
        if (verb == "key") {
            e.kind = InputEvent::Kind::key;
            std::string name = rest;
            for (bool more = true; more;) {
                more = false;
                if (name.rfind("ctrl+", 0) == 0) e.ctrl = more = true, name.erase(0, 5);
                if (name.rfind("shift+", 0) == 0) e.shift = more = true, name.erase(0, 6);
            }
            e.key = key_code(name);
            if (e.key < 0) fail("no key '" + rest + "' (a letter, a digit, space, Return, Right, Left, ...)");
        } else if (verb == "text") {
            e.kind = InputEvent::Kind::text;
            e.text = rest;
            if (rest.empty()) fail("text with nothing to type");
        } else if (verb == "move") {
            e.kind = InputEvent::Kind::move;
            std::istringstream xy(rest);
            std::string x, y, extra;
            if (rest.rfind('@', 0) == 0 && rest.size() > 1) {
                e.text = rest.substr(1);
            } else if (!(xy >> x >> y) || (xy >> extra) || !number(x, e.x) || !number(y, e.y)) {
                fail("move needs X Y in window pixels, or @LABEL of a panel item (got '" + rest + "')");
            }
        } else if (verb == "press" || verb == "release") {
            e.kind = verb == "press" ? InputEvent::Kind::press : InputEvent::Kind::release;
            std::istringstream b(rest);
            std::string name, modifier, extra;
            b >> name >> modifier >> extra;
            e.key = button_code(name);
            e.shift = modifier == "shift";
            e.ctrl = modifier == "ctrl";
            if (e.key < 0 || (!modifier.empty() && !e.shift && !e.ctrl) || !extra.empty()) {
                fail(verb + " needs left, right or middle, then optionally shift or ctrl (got '" + rest + "')");
            }
        } else {
            fail("no event '" + verb + "' (key, text, move, press or release)");
        }
        events.push_back(std::move(e));
    }
    return events;
}

}  // namespace scenes::view
