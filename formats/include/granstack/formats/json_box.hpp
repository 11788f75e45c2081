#pragma once
// A JSON value held by a struct whose header should not bring in nlohmann/json.hpp (the
// manifest's informative fields, a run's record): a box with value semantics (copies are deep).
// Its readers include nlohmann/json.hpp and reach the value through * and ->.
#include <nlohmann/json_fwd.hpp>

#include <memory>

namespace granstack::formats {

class JsonBox {
 public:
  JsonBox();  // null, as nlohmann::json() is
  JsonBox(const nlohmann::json& value);  // NOLINT(google-explicit-constructor): a box of the value
  JsonBox(nlohmann::json&& value);       // NOLINT(google-explicit-constructor)
  JsonBox(const JsonBox& other);
  JsonBox(JsonBox&& other) noexcept;
  JsonBox& operator=(const JsonBox& other);
  JsonBox& operator=(JsonBox&& other) noexcept;
  ~JsonBox();

  nlohmann::json& operator*() { return *value_; }
  const nlohmann::json& operator*() const { return *value_; }
  nlohmann::json* operator->() { return value_.get(); }
  const nlohmann::json* operator->() const { return value_.get(); }

 private:
  std::unique_ptr<nlohmann::json> value_;  // null only in a moved-from box, which may only be assigned or destroyed
};

}  // namespace granstack::formats
