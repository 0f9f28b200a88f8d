// A string as JSON text, for the files the renderer and the grader write.
#pragma once
#include <string>

namespace pt {

// "text" with quotes, backslashes, newlines and other control characters
// escaped.
std::string json_quote(const std::string& s);

}  // namespace pt
