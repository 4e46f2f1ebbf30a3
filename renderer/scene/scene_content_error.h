// A scene that loaded but cannot be rendered as it stands: geometry or a camera past what a ray
// can reach, a camera transform that gives no view. The scene's content is at fault, not an
// argument of the call, so the C API reports it as bad input (VEACH_ERROR_BAD_INPUT, the
// command's exit 2) like any other fault of the file. A re-posed animated scene can reach such a
// pose at any frame, which is why the check is made where a render starts.
#pragma once

#include <stdexcept>

namespace veach {

struct SceneContentError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

}  // namespace veach
