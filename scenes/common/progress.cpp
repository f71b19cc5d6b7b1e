#include "scenes/common/progress.h"

#include <unistd.h>

#include <cstdlib>
#include <string_view>

namespace scenes {

bool progress_wanted() {
    const char* ci = std::getenv("CI");
    return isatty(STDERR_FILENO) != 0 && (ci == nullptr || std::string_view(ci) != "true");
}

}  // namespace scenes
