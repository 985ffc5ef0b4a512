// SPDX-License-Identifier: LGPL-2.1-or-later
// Changing a scene: RFC 7396 merge patches (a null restoring the scene's own
// value) and the CLI's key.path=value assignments. The result goes through
// scene_from_json, so a patch is validated like a whole scene.
#include "caustic/json_text.hpp"
#include "caustic/scene.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace caustic {

using nlohmann::json;

namespace {

// RFC 7396's null removes a member, which here would fall back to the global
// default; a visitor's "reset" means the scene's own value instead. Each null
// of the patch becomes the origin's value at that place (a null where the
// origin has none stays null: the default). Recursion follows the patch, so
// its depth is the patch's (bounded by the JSON parser).
json nulls_to_origin(const json& patch, const json* origin) {
  json out = json::object();
  for (const auto& [k, v] : patch.items()) {
    const json* here = origin && origin->is_object() && origin->contains(k) ? &origin->at(k) : nullptr;
    if (v.is_null()) out[k] = here ? *here : json(nullptr);
    else if (v.is_object()) out[k] = nulls_to_origin(v, here);
    else out[k] = v;
  }
  return out;
}

// The first key path the patch writes within `value` ("water.grid"), or
// `path` itself when it writes none below it.
std::string first_key(const json& value, const std::string& path) {
  if (!value.is_object() || value.empty()) return path;
  return first_key(value.begin().value(), path + "." + printable_name(value.begin().key(), 64));
}

// A patch that brings one kind of scene's keys to another: the merged
// scene holds the shape the scene has (scene_to_json writes it), so the
// refusal would name object.shape, which the patch never wrote. It is said
// of the key written, with the shape the scene has.
void check_scene_kind(const Scene& scene, const json& doc, const json& patch) {
  // A shape the patch writes is the patch's to answer for, by its own key.
  const auto object = patch.find("object");
  if (object != patch.end() && object->is_object() && object->contains("shape")) return;
  const std::string shape = doc.at("object").at("shape").get<std::string>();
  // So is a mirror made of a solid or a surface (it was said of object.shape).
  if (object != patch.end() && object->is_object() && object->value("material", json()) == "reflective" &&
      shape != "slab")
    throw SceneError("object.material", "\"reflective\" makes a mirror of a slab's face; this scene's object is a " +
                                            shape + " (object.shape \"" + shape +
                                            "\"), which light passes through: it must be \"refractive\"");
  const auto water = patch.find("water");
  if (water == patch.end()) return;
  if (!scene.water && !water->is_null() && shape != "surface")
    throw SceneError(first_key(*water, "water"), "belongs to a water scene, and this scene has no water: its object "
                                                 "is a " + shape + " (object.shape \"" + shape +
                                                     "\"), read from its mesh file");
  if (scene.water && water->is_null() && !patch.contains("mesh"))
    throw SceneError("water", "is this scene's object (object.shape \"surface\", made by the wave solver): without "
                              "it the scene has none; a scene without water names its face in mesh");
}

// Whether `text` is a number by JSON's grammar (RFC 8259 §6), blanks about it.
bool json_number(const std::string& text) {
  std::size_t at = text.find_first_not_of(" \t");
  const auto digits = [&] {
    const std::size_t from = at;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') ++at;
    return at > from;
  };
  if (at == std::string::npos) return false;
  if (text[at] == '-') ++at;
  if (at < text.size() && text[at] == '0') ++at;
  else if (!digits()) return false;
  if (at < text.size() && text[at] == '.' && (++at, !digits())) return false;
  if (at < text.size() && (text[at] == 'e' || text[at] == 'E')) {
    ++at;
    if (at < text.size() && (text[at] == '+' || text[at] == '-')) ++at;
    if (!digits()) return false;
  }
  return text.find_first_not_of(" \t", at) == std::string::npos;
}

}  // namespace

Scene apply_merge_patch(const Scene& scene, const json& patch, const Scene* origin) {
  if (origin && patch.is_object()) {
    const json origin_doc = scene_to_json(*origin);
    return apply_merge_patches(scene, {nulls_to_origin(patch, &origin_doc)});
  }
  return apply_merge_patches(scene, {patch});
}

Scene apply_merge_patches(const Scene& scene, const std::vector<json>& patches) {
  // A shape written by any patch answers for the keys the others bring.
  const bool shape_written = std::any_of(patches.begin(), patches.end(), [](const json& patch) {
    const auto object = patch.find("object");
    return object != patch.end() && object->is_object() && object->contains("shape");
  });
  json doc = scene_to_json(scene);
  for (const auto& patch : patches) {
    if (!patch.is_object()) throw SceneError("", "a parameter patch must be a JSON object");
    // Files are the scene file's to name: a patch that could would open them.
    if (patch.contains("receiver_meshes"))
      throw SceneError("receiver_meshes", "belongs to the scene file; a patch may use its shapes, not list files");
    // The screen centre is stored resolved; a patch of focus_distance alone
    // should move the screen, so drop the centre unless the patch sets it.
    if (patch.contains("focus_distance") && !(patch.contains("screen") && patch["screen"].contains("center")))
      doc["screen"].erase("center");
    if (!shape_written) check_scene_kind(scene, doc, patch);
    doc.merge_patch(patch);
  }
  return scene_from_json(doc, scene.base_dir, scene.receiver_meshes);
}

json patch_from_assignment(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) throw SceneError("", "expected key.path=value, got \"" + assignment + "\"");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  // A value that is not JSON is the string written: --set object.glass=bk7;
  // one that opens an object or an array was meant as JSON, and its error is said.
  JsonTextError error;
  auto parsed = parse_json_text(text, &error);
  const auto first = text.find_first_not_of(" \t");
  // So was a number JSON's grammar allows but a double cannot hold (1e400):
  // taken as a string, it was refused as "must be a number".
  if (!parsed && first != std::string::npos && (text[first] == '{' || text[first] == '[' || json_number(text)))
    throw SceneError(path, "not valid JSON: " + where_json_broke(text, error));
  json value = parsed ? std::move(*parsed) : json(text);
  // A scene's keys lie at most a few deep: a longer path names no key, and
  // is refused before it is built (nested level by level, a path of 20,000
  // keys once took 40 s).
  constexpr std::size_t kMaxDepth = 8;
  if (static_cast<std::size_t>(std::count(path.begin(), path.end(), '.')) >= kMaxDepth)
    throw SceneError(path.size() > 64 ? path.substr(0, 64) + "..." : path,
                     "a key path of more than " + std::to_string(kMaxDepth) + " keys names no scene key");
  std::vector<std::string> keys;
  std::size_t begin = 0;
  while (true) {
    const auto dot = path.find('.', begin);
    keys.push_back(path.substr(begin, dot == std::string::npos ? std::string::npos : dot - begin));
    if (keys.back().empty()) throw SceneError(path, "empty key in path");
    if (dot == std::string::npos) break;
    begin = dot + 1;
  }
  json patch = std::move(value);
  for (auto it = keys.rbegin(); it != keys.rend(); ++it) patch = json{{*it, std::move(patch)}};
  return patch;
}

}  // namespace caustic
