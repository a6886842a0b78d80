#pragma once
// A recorded run (view/recording.h) as one self-contained HTML page that plays it: three.js
// (Debian's libjs-three, r111) and its OrbitControls inlined, the frames as base64 typed arrays
// in a JSON block, the page's own script from view/viewer.html (compiled in). The page draws the
// bodies by their shapes, the joints' anchors, the contacts' impulses as arrows, a time slider,
// play and pause, the speed, and a plot of the separation and penetration against time; opened
// as page.html#t=1.5 it shows that time, paused, and logs a check of what it drew (the browser
// test, tests/view/view_browser_test.py).
#include <cstddef>
#include <ostream>
#include <string>

#include "view/recording.h"

namespace ldlpgs::view {

// RFC 4648 base64 (with padding) of `bytes` bytes.
std::string base64(const void* data, size_t bytes);

// The page's data block: JSON, with every '<' written as \u003c so that nothing in it (a body
// named "</script>") can end the script element holding it.
std::string page_data(const Recording& recording);

void write_html(const Recording& recording, std::ostream& out);

}  // namespace ldlpgs::view
