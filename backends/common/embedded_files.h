#pragma once
// The GLSL sources of shaders/, compiled into the binary so that it runs from any directory.

#include <map>
#include <string>

namespace omnishadow {

const std::map<std::string, std::string>& embedded_files();  // file name ("lighting.frag") -> text

}  // namespace omnishadow
