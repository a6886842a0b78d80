// The viewer from Python: sim.record() keeps the following steps (view/recording.h), sim.view()
// returns the page that plays them (view/html.h) as an object a notebook shows (_repr_html_:
// the page in an iframe) or saves.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "bindings.h"
#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "view/html.h"
#include "view/recording.h"

namespace ldlpgs::python {

namespace py = pybind11;

namespace {

// The page, as the notebook and a file get it.
struct Page {
  std::string html;
  int frames = 0;
};

// `text` quoted for an HTML attribute value in double quotes.
std::string attribute(const std::string& text) {
  std::string out;
  out.reserve(text.size() + text.size() / 8);
  for (char c : text) {
    if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

constexpr const char* kRecording = "_ldlpgs_recording";  // the Simulation's attribute holding it

}  // namespace

view::Recording* recording_of(py::handle simulation) {
  if (!py::hasattr(simulation, kRecording)) return nullptr;
  return simulation.attr(kRecording).cast<view::Recording*>();
}

void bind_view(py::module_& m) {
  py::class_<view::Recording>(m, "Recording", "Steps kept for the viewer (Simulation.record, view/recording.h).")
      .def_property_readonly("frames", &view::Recording::frames)
      .def_property_readonly("steps", &view::Recording::steps);
  py::class_<Page>(m, "View", "A page that plays a recorded run (Simulation.view): html, save(path), and "
                              "_repr_html_ for a notebook (the page in an iframe).")
      .def_readonly("html", &Page::html, "The self-contained HTML page (three.js inlined).")
      .def_readonly("frames", &Page::frames)
      .def(
          "save",
          [](const Page& p, const std::filesystem::path& path) {
            std::ofstream out(path, std::ios::binary);
            out << p.html;
            out.close();
            if (!out) throw InputError(path.string() + ": cannot write the HTML file");
          },
          py::arg("path"), "Writes the page to path (what `ldlpgs view --html-file` writes).")
      .def("_repr_html_", [](const Page& p) {
        return "<iframe srcdoc=\"" + attribute(p.html) +
               "\" style=\"width: 100%; height: 600px; border: 1px solid #ccc\"></iframe>";
      });

  py::object simulation = m.attr("Simulation");
  simulation.attr("record") = py::cpp_function(
      [](py::object self, double frame_rate, int max_frames) {
        if (!(frame_rate > 0) || !std::isfinite(frame_rate)) throw InputError("frame_rate must be finite and > 0");
        if (max_frames < 2) throw InputError("max_frames must be at least 2");
        view::RecordOptions o;
        o.frame_rate = frame_rate;
        o.max_frames = max_frames;
        self.attr(kRecording) = py::cast(view::Recording(self.cast<const Simulation&>(), o));
      },
      py::name("record"), py::is_method(simulation), py::arg("frame_rate") = view::RecordOptions{}.frame_rate,
      py::arg("max_frames") = view::RecordOptions{}.max_frames,
      "Keeps the steps from now on for view(): a frame at most frame_rate times per simulated second, "
      "halved past max_frames (the separation and penetration need diagnostics=True). Again: starts over.");
  simulation.attr("view") = py::cpp_function(
      [](py::object self) {
        const Simulation& sim = self.cast<const Simulation&>();
        std::optional<view::Recording> now;  // without record(): the current pose alone
        view::Recording* recording = recording_of(self);
        if (recording) recording->finish(sim);
        else recording = &now.emplace(sim);
        std::ostringstream out;
        view::write_html(*recording, out);
        return Page{out.str(), recording->frames()};
      },
      py::name("view"), py::is_method(simulation),
      "The recorded run (record()) up to now as a View: shown by a notebook, or save(path). Without "
      "record(), the current pose alone.");
}

}  // namespace ldlpgs::python
