// Options structs that list their own fields by name, and the one function that builds a cache key from such
// a list (options_key). A cached result is looked up by its options' key, so a field left out of the key
// would serve results computed with another value of it: listing every field in the struct itself, beside its
// declaration, and building every key from that list is what keeps keys from going stale
// (tests/options_key_test.cpp proves that each list names every member and that each field reaches the key).
//
// An options struct lists its fields in a static member template, in declaration order:
//
//   struct KnnGraphOptions {
//     int k = 8;
//     // Every field by name (support/option_fields.h). Self: KnnGraphOptions, const or not.
//     template <class Self, class Visit>
//     static void for_each_field(Self& o, Visit&& visit) {
//       visit("k", o.k);
//     }
//   };
//
// visit(name, field) for a field that changes the result (the default: when unsure, it does);
// visit(name, field, kNoEffect) for one that does not (a progress callback, a name used in messages), with a
// comment saying why; visit(name, path, kFileContent) for a file path whose content, not its name, is an
// input. A static member function keeps the struct an aggregate (brace initialisation works, and the test
// counts its members). A visitor is any callable taking (const char* name, Field& field, Effect... effect),
// e.g. a generic lambda [&](const char* name, auto& field, auto... effect).
#pragma once

#include <map>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "cshapes/support/sha256.h"
#include "cshapes/support/types.h"

namespace cshapes {

// The marks of fields that do not enter a key by their value.
// Does not change the result: left out of the key.
struct NoEffect {};
// A file path (std::string) whose content, not its name, changes the result: the content's SHA-256 enters the
// key.
struct FileContent {};
inline constexpr NoEffect kNoEffect{};
inline constexpr FileContent kFileContent{};

// Whether the marks a visitor received (their types, e.g. decltype(effect)...) say the field changes the
// result / is a file whose content does.
template <class... Effect>
inline constexpr bool changes_result = !(std::is_same_v<Effect, NoEffect> || ...);
template <class... Effect>
inline constexpr bool is_file_content = (std::is_same_v<Effect, FileContent> || ...);

namespace detail {
struct AnyFieldVisitor {
  template <class Field, class... Effect>
  void operator()(const char*, Field&, Effect...) const {}
};
}  // namespace detail

// Whether T lists its fields (a static for_each_field as above).
template <class T, class = void>
struct has_field_list : std::false_type {};
template <class T>
struct has_field_list<T,
                      std::void_t<decltype(T::for_each_field(std::declval<T&>(), detail::AnyFieldVisitor{}))>>
    : std::true_type {};

// A vector's values longer than this many characters of key text enter the key as their count and the SHA-256
// of that text (SMACOF's n vertex weights), so a key stays short.
inline constexpr size_t kKeyValueHashAbove = 256;

namespace detail {

template <class T>
struct is_std_vector : std::false_type {};
template <class T, class A>
struct is_std_vector<std::vector<T, A>> : std::true_type {};

template <class T>
struct is_string_map : std::false_type {};
template <class C, class A>
struct is_string_map<std::map<std::string, std::string, C, A>> : std::true_type {};

template <class T>
constexpr bool is_eigen_vector() {
  if constexpr (std::is_base_of_v<Eigen::EigenBase<T>, T>)
    return T::ColsAtCompileTime == 1;
  else
    return false;
}

template <class Value>
void append_key_value(std::string& text, const Value& value);

template <class Sequence>
void append_key_values(std::string& text, const Sequence& values, size_t count) {
  std::string all;
  for (size_t k = 0; k < count; ++k) {
    append_key_value(all, values[static_cast<decltype(values.size())>(k)]);
    all += ',';
  }
  if (all.size() > kKeyValueHashAbove) all = "n:" + std::to_string(count) + ",sha256:" + sha256_hex(all);
  text += all;
}

// One value as key text (see options_key).
template <class Value>
void append_key_value(std::string& text, const Value& value) {
  if constexpr (std::is_same_v<Value, bool>) {
    text += value ? '1' : '0';
  } else if constexpr (std::is_arithmetic_v<Value>) {
    std::ostringstream out;
    out.precision(17);  // round-trips a double; integers print exactly
    out << value;
    text += out.str();
  } else if constexpr (std::is_enum_v<Value>) {
    text += to_string(value);  // every option enum has one, found by argument-dependent lookup
  } else if constexpr (std::is_same_v<Value, std::string>) {
    text += '"';
    for (char c : value) {
      if (c == '"' || c == '\\') text += '\\';
      text += c;
    }
    text += '"';
  } else if constexpr (is_std_vector<Value>::value) {
    append_key_values(text, value, value.size());
  } else if constexpr (is_eigen_vector<Value>()) {
    append_key_values(text, value, static_cast<size_t>(value.size()));
  } else if constexpr (is_string_map<Value>::value) {
    for (const auto& [name, item] : value) {  // in the map's (sorted) order: "name"="value",
      append_key_value(text, name);
      text += '=';
      append_key_value(text, item);
      text += ',';
    }
  } else {
    static_assert(sizeof(Value) == 0,
                  "this field's type cannot enter a cache key: mark it kNoEffect (and say why) or list the "
                  "fields of its struct");
  }
}

// The visitor behind options_key: "prefix.name=value" per field that changes the result.
class OptionsKeyWriter {
 public:
  using Include = bool (*)(const void* context, const char* name);
  OptionsKeyWriter(std::string& text, std::string prefix, Include include = nullptr,
                   const void* context = nullptr)
      : text_(text), prefix_(std::move(prefix)), include_(include), context_(context) {}

  template <class Field, class... Effect>
  void operator()(const char* name, const Field& field, Effect...) {
    if constexpr (changes_result<Effect...>) {
      if (include_ && !include_(context_, name)) return;
      if constexpr (has_field_list<Field>::value) {
        OptionsKeyWriter nested(text_, prefix_ + name + ".");
        Field::for_each_field(field, nested);
      } else {
        if (!text_.empty()) text_ += ';';
        text_ += prefix_;
        text_ += name;
        text_ += '=';
        if constexpr (is_file_content<Effect...>) {
          static_assert(std::is_same_v<Field, std::string>, "kFileContent marks a path (std::string)");
          if (!field.empty()) text_ += file_content_hash(field);
        } else {
          append_key_value(text_, field);
        }
      }
    }
  }

 private:
  std::string& text_;
  std::string prefix_;
  Include include_;  // asked for top-level fields only
  const void* context_;
};

}  // namespace detail

// The options as one canonical text for cache keys: "name=value" for every field that changes the result,
// in the list's order, joined by ';'; a nested options struct's fields as "outer.inner=value". Values:
// numbers with 17 significant digits (a double round-trips, an integer is exact), bools 1 or 0, enums by
// their to_string, strings quoted ("…", with \" and \\ escaped), a kFileContent path by the SHA-256 of the
// file's content (nothing when the path is empty; throws naming a file it cannot read), a vector (std::vector
// or an Eigen column vector) by its values, each followed by ',' — or, when that text is longer than
// kKeyValueHashAbove characters, by "n:<count>,sha256:<SHA-256 of that text>"; a std::map of strings by its
// entries, "name"="value", each followed by ','. Equal texts mean equal values of every listed field that
// changes the result.
// include(name), when given, is asked for each top-level field: false leaves the field out (a canonical
// form's key leaves out the options its method does not read).
template <class Options>
std::string options_key(const Options& options) {
  static_assert(has_field_list<Options>::value, "options_key needs a struct that lists its fields");
  std::string text;
  detail::OptionsKeyWriter writer(text, "");
  Options::for_each_field(options, writer);
  return text;
}
template <class Options, class Include>
std::string options_key(const Options& options, const Include& include) {
  static_assert(has_field_list<Options>::value, "options_key needs a struct that lists its fields");
  std::string text;
  detail::OptionsKeyWriter writer(
      text, "",
      [](const void* context, const char* name) { return (*static_cast<const Include*>(context))(name); },
      &include);
  Options::for_each_field(options, writer);
  return text;
}

}  // namespace cshapes
