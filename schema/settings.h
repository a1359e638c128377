#pragma once
// One place per setting: a capability binds each field of its options struct once, with its name, description and
// bounds (`Bind<Capability>Settings(SettingsBinder&, Options&)` beside the struct). The server loads values into the
// bound fields (file, environment, flags) and generates `--help` and `GET /v1/settings` from the same bindings.
// The default of a setting is the field's initialiser; nothing else repeats it.
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace anchordb {

// A bound as an ostream prints a double (1e+06, 0.7854, 65).
std::string FormatBound(double v);

using SettingValue = std::variant<bool, std::int64_t, double, std::string>;

struct SettingInfo {
  std::string name;         // snake_case; flag --name, environment ANCHORDB_NAME
  std::string type;         // int, number, string, bool
  std::string description;  // with the unit in brackets where it has one
  double min = -std::numeric_limits<double>::infinity();  // bounds of numbers (inclusive)
  double max = std::numeric_limits<double>::infinity();
};

class SettingsBinder {
 public:
  struct Entry {
    SettingInfo info;
    std::function<void(const std::string& text)> set;  // throws std::invalid_argument naming the setting
    std::function<SettingValue()> get;
  };

  // Binds `field` (which must outlive the binder) under `name`. Numbers outside [lo, hi] are refused.
  template <typename T>
  void Bind(std::string name, std::string description, T* field,
            double lo = -std::numeric_limits<double>::infinity(), double hi = std::numeric_limits<double>::infinity());

  // A rule over several fields (e.g. free_max below occupied_min), checked by Validate(); throws
  // std::invalid_argument with its message.
  void Require(std::function<bool()> holds, std::string message) {
    checks_.push_back({std::move(holds), std::move(message)});
  }

  void Validate() const {
    for (const auto& c : checks_) {
      if (!c.holds()) throw std::invalid_argument("settings: " + c.message);
    }
  }

  // `name` with '-' read as '_'; nullptr when no setting has that name.
  const Entry* Find(std::string name) const {
    for (char& ch : name) ch = ch == '-' ? '_' : ch;
    for (const Entry& e : entries_) {
      if (e.info.name == name) return &e;
    }
    return nullptr;
  }

  const std::vector<Entry>& entries() const { return entries_; }

 private:
  struct Check {
    std::function<bool()> holds;
    std::string message;
  };
  std::vector<Entry> entries_;
  std::vector<Check> checks_;
};

template <typename T>
void SettingsBinder::Bind(std::string name, std::string description, T* field, double lo, double hi) {
  static_assert(std::is_same_v<T, std::string> || std::is_same_v<T, bool> || std::is_arithmetic_v<T>);
  Entry e;
  const char* type = std::is_same_v<T, std::string> ? "string"
                     : std::is_same_v<T, bool>      ? "bool"
                     : std::is_integral_v<T>        ? "int"
                                                    : "number";
  e.info = {name, type, std::move(description), lo, hi};
  e.set = [name, field, lo, hi](const std::string& text) {
    (void)lo;  // unused for strings and bools (clang warns of an unused capture)
    (void)hi;
    if constexpr (std::is_same_v<T, std::string>) {
      *field = text;
    } else if constexpr (std::is_same_v<T, bool>) {
      if (text == "true" || text == "1") *field = true;
      else if (text == "false" || text == "0") *field = false;
      else throw std::invalid_argument("setting " + name + ": '" + text + "' is not true or false");
    } else {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
        throw std::invalid_argument("setting " + name + ": '" + text + "' is not a number");
      }
      if (std::is_integral_v<T> && v != std::floor(v)) throw std::invalid_argument("setting " + name + ": must be an integer");
      if (v < lo || v > hi) {
        throw std::invalid_argument("setting " + name + ": " + text + " is outside [" + FormatBound(lo) + ", " +
                                    FormatBound(hi) + "]");
      }
      *field = static_cast<T>(v);
    }
  };
  e.get = [field]() -> SettingValue {
    if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, bool>) return *field;
    else if constexpr (std::is_integral_v<T>) return static_cast<std::int64_t>(*field);
    else return static_cast<double>(*field);
  };
  entries_.push_back(std::move(e));
}

}  // namespace anchordb
