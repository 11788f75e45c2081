#include <granstack/formats/json_box.hpp>

#include <nlohmann/json.hpp>

namespace granstack::formats {

JsonBox::JsonBox() : value_(std::make_unique<nlohmann::json>()) {}
JsonBox::JsonBox(const nlohmann::json& value) : value_(std::make_unique<nlohmann::json>(value)) {}
JsonBox::JsonBox(nlohmann::json&& value) : value_(std::make_unique<nlohmann::json>(std::move(value))) {}
JsonBox::JsonBox(const JsonBox& other) : value_(std::make_unique<nlohmann::json>(*other.value_)) {}
JsonBox::JsonBox(JsonBox&& other) noexcept : value_(std::move(other.value_)) {}
JsonBox& JsonBox::operator=(const JsonBox& other) {
  if (this != &other) *value_ = *other.value_;
  return *this;
}
JsonBox& JsonBox::operator=(JsonBox&& other) noexcept {
  std::swap(value_, other.value_);
  return *this;
}
JsonBox::~JsonBox() = default;

}  // namespace granstack::formats
