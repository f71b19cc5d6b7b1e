// libFuzzer target: the bytes of a `view --input` script through its parser
// (scenes/view/input_script.h; no window, no GL). A script either parses or
// is refused with an InputError naming its line; everything else is a
// finding, as for fuzz_scene.cpp.
#include "scenes/view/input_script.h"
#include "sim/error.h"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        scenes::view::parse_input_script(in, "fuzz.txt");
    } catch (const sim::InputError&) {
        // refused with a message: what bad input should get
    }
    return 0;
}
