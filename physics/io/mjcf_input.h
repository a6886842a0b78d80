#pragma once
// Internal to physics/: the MJCF file's text checked before MuJoCo reads it (mjcf.cpp's
// load_mjcf). MuJoCo reads nan and inf, and a hinge axis "nan 0 0" makes mj_loadXML never return.
#include <string>

namespace ldlpgs {

// Refuses (InputError, naming file, line, element and attribute) an MJCF file, or a file it
// includes, that is not XML text of a plausible size or whose numeric attributes are not finite
// numbers. Numeric: the attributes MuJoCo 2.2.2's schema reads as real numbers, read as MuJoCo
// reads them; keywords (<flag gravity="disable"/>) and strings are MuJoCo's to check. What MuJoCo
// loads with finite numbers passes. A missing file passes: MuJoCo names what is missing.
void check_mjcf_numbers(const std::string& path);

}  // namespace ldlpgs
