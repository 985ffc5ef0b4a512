// SPDX-License-Identifier: LGPL-2.1-or-later
// Checks a JSON response against docs/openapi.json: the documented status,
// content type and schema (type, required, properties, items, enum, $ref).
#pragma once

#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

namespace caustic::testing {

class OpenApi {
 public:
  OpenApi() {
    std::ifstream in(CAUSTIC_OPENAPI);
    doc_ = nlohmann::json::parse(in);
  }

  /// "" when `body` (of `content_type`) is what the document promises for
  /// `method` on `path` (the template, e.g. /api/v1/sessions/{id}) with `status`.
  std::string check(const std::string& path, const std::string& method, unsigned status,
                    const std::string& content_type, const nlohmann::json& body) const {
    const auto& op = doc_["paths"].value(path, nlohmann::json::object()).value(method, nlohmann::json());
    if (op.is_null()) return method + " " + path + " is not documented";
    nlohmann::json response = op["responses"].value(std::to_string(status), nlohmann::json());
    if (response.is_null()) return method + " " + path + ": status " + std::to_string(status) + " is not documented";
    response = resolve(response);
    if (!response.contains("content")) return body.is_null() ? "" : "documented without a body";
    if (!response["content"].contains(content_type)) return "content type " + content_type + " is not documented";
    const auto& media = response["content"][content_type];
    return media.contains("schema") ? validate(resolve(media["schema"]), body, "body") : "";
  }

 private:
  nlohmann::json resolve(const nlohmann::json& node) const {
    if (!node.is_object() || !node.contains("$ref")) return node;
    const std::string ref = node["$ref"];  // "#/components/schemas/X"
    return resolve(doc_.at(nlohmann::json::json_pointer(ref.substr(1))));
  }

  std::string validate(const nlohmann::json& schema, const nlohmann::json& value, const std::string& where) const {
    const std::string type = schema.value("type", "");
    auto fail = [&](const std::string& why) { return where + ": " + why; };
    if (value.is_null() && schema.value("nullable", false)) return "";
    if (type == "object" && !value.is_object()) return fail("expected an object");
    if (type == "array" && !value.is_array()) return fail("expected an array");
    if (type == "string" && !value.is_string()) return fail("expected a string");
    if (type == "integer" && !value.is_number_integer()) return fail("expected an integer");
    if (type == "number" && !value.is_number()) return fail("expected a number");
    if (type == "boolean" && !value.is_boolean()) return fail("expected a boolean");
    if (schema.contains("enum") && std::find(schema["enum"].begin(), schema["enum"].end(), value) == schema["enum"].end())
      return fail("not one of the documented values");
    if (value.is_object()) {
      for (const auto& key : schema.value("required", nlohmann::json::array()))
        if (!value.contains(key.get<std::string>())) return fail("lacks required \"" + key.get<std::string>() + "\"");
      const auto properties = schema.value("properties", nlohmann::json::object());
      for (const auto& [key, sub] : value.items()) {
        if (properties.contains(key)) {
          if (auto e = validate(resolve(properties[key]), sub, where + "." + key); !e.empty()) return e;
        } else if (!properties.empty()) {
          return fail("has undocumented \"" + key + "\"");
        }
      }
    }
    if (value.is_array() && schema.contains("items"))
      for (std::size_t i = 0; i < value.size(); ++i)
        if (auto e = validate(resolve(schema["items"]), value[i], where + "[" + std::to_string(i) + "]"); !e.empty())
          return e;
    return "";
  }

  nlohmann::json doc_;
};

}  // namespace caustic::testing
