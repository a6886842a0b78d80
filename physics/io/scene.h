#pragma once
// Scene files: a mechanism in JSON (nlohmann-json), anchors and axes in the world frame at the
// initial pose (format in README.md, "Scene files"). Everything wrong in a file is an InputError
// naming the file and the entry ("chain.json: constraints[3]: unknown body \"link9\""), never a
// crash or a silent default.
#include <string>

#include <nlohmann/json.hpp>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs {

// `source` names the file in messages.
Mechanism parse_scene(const nlohmann::json& scene, const std::string& source);
Mechanism load_scene(const std::string& path);  // also refuses unreadable files and bad JSON

// The mechanism at its current pose in the same format (parse_scene(scene_to_json(m)) rebuilds m
// up to rounding). The file's pose becomes the new initial pose: a limit's zero and a weld's or
// prismatic's reference orientation are those of the saved pose, as the format defines them.
nlohmann::json scene_to_json(const Mechanism& mechanism);
void save_scene(const Mechanism& mechanism, const std::string& path);

}  // namespace ldlpgs
