#pragma once
// Reading the page's JSON requests: each reader names the field it refuses, so that every bad
// request gets a 4xx saying what to change (explore_api.cpp turns RequestError into the answer).
#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>

#include "explore_api.h"

namespace thicket::explore {

using nlohmann::json;

/// A request the server refuses: the HTTP status (4xx) and the message the page shows.
struct RequestError : std::runtime_error {
    int status;
    RequestError(int s, const std::string& what) : std::runtime_error(what), status(s) {}
};

/// The request body as a JSON object (400 for text that is not JSON or not an object).
json parse_body(const std::string& body);
/// body[key] as a whole number within [lo, hi]; `fallback` when absent if `required` is false.
uint32_t read_uint(const json& body, const char* key, uint32_t lo, uint32_t hi, bool required, uint32_t fallback = 0);
/// body[key] as three finite numbers.
Vec3 read_vec3(const json& body, const char* key);
/// The camera of body["camera"] ({eye, target, up, fov}) with body's width and height
/// (1..kMaxImageSide each); eye and target must differ, up must not be parallel to the view.
View read_view(const json& body);
/// body["structure"] as an index into `count` structures, or the spec one was built with.
size_t read_structure(const json& body, const std::vector<std::string>& specs);
/// {"error": message} with `status`.
Response error_response(int status, const std::string& message);
/// A JSON answer with status 200.
Response json_response(const json& j);
/// A box as [minx, miny, minz, maxx, maxy, maxz].
json box_json(const Aabb& b);

}  // namespace thicket::explore
