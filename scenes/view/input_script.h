// A scripted session for the viewer (`view --input FILE`): key, text and
// mouse events, each at a frame the window draws (its loop's iteration,
// from 1), so that a test drives the viewer by frames, not by a wall clock:
// the same script gives the same frames and the same bits on a loaded
// machine. While a script drives it, a running scene steps once per drawn
// frame (as with --exit-after). One event per line, # starts a comment:
//   3 key Right            a key: a letter, a digit, space, Return, Right,
//   4 key ctrl+a           Left, Up, Down, Escape, BackSpace, Tab, period,
//                          comma, bracketleft, bracketright; ctrl+ and
//                          shift+ hold those while it is pressed
//   5 text 0.3             typed text (where the panel takes text)
//   6 move 960 284         the cursor to window coordinates (px)
//   6 move @colliders[0].radius   ... or to the middle of a panel item, by
//                          its label, where the panel last drew it
//   7 press left           a mouse button down (left, right, middle), at
//   8 release left         the cursor; press left shift (or ctrl): with
//                          that key held (ctrl+click types into a slider)
// Frames do not decrease; events of one frame run in the file's order. A key
// is down for its frame and up the next. The panel learns where the cursor
// is when it draws, so press a frame after a move onto it; and it takes its
// size and place in its first frames, so move onto its items after a few.
// (Tests: tests/scenes/view/view_test.cpp.)
#pragma once

#include <filesystem>
#include <istream>
#include <string>
#include <vector>

namespace scenes::view {

struct InputEvent {
    enum class Kind { key, text, move, press, release };
    int frame = 1;  // the window's frame it happens at, from 1
    Kind kind = Kind::key;
    int key = 0;  // key: the GLFW key; press, release: the GLFW mouse button
    bool ctrl = false, shift = false;
    std::string text;     // text: what is typed; move: a panel item's label, or empty
    double x = 0, y = 0;  // move without a label: window coordinates, px
    std::string where;    // "FILE:LINE", for what goes wrong later (an item never drawn)
};

// Reads a script; InputError naming the file, the line and what is wrong.
std::vector<InputEvent> read_input_script(const std::filesystem::path& file);
// The same over a script's text (`file` names it in messages): what the
// fuzzer (tools/fuzz) drives, without a window.
std::vector<InputEvent> parse_input_script(std::istream& in, const std::string& file);

}  // namespace scenes::view
