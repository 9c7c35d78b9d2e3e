// A parameter block declared once. Each key of a YAML block (the servo
// program's `speed_law`, `safety`, ...) is one Field: its name, the member it
// fills, its unit, its valid range or choices, and a one-line meaning; its
// default is the member's initial value in the struct. From that one
// declaration come:
//   * the reader, with its unknown-key errors (tactile_config/schema_yaml.hpp);
//   * the range checks and their messages, checkRanges() below, which the
//     cores' configure() call, so that a struct filled in code is checked as
//     a file is;
//   * the key tables of docs/formats.md (markdownTable(), `tactile_sim schema`,
//     checked by ctest docs_parameter_tables).
// A key is added in one place: a member in the struct, a row in its Block.
//
// Ranges are written as the docs show them: "(0, 1]", "[0, 10]", "[0, v_max]"
// (an end may name another number of the same block: its current value),
// ">= 0", "> 0", or "" (any finite number). Numbers are compared in the
// file's unit; a Field with a conversion (degrees in the file, radians in the
// struct) converts as member = value * mul / div.
//
// Configuration time only: these functions allocate and are never called
// from a cycle.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "tactile_types/config_result.hpp"

namespace tactile {
namespace schema {

enum class Kind : std::uint8_t {
  Number,   ///< a finite double, with a range
  Integer,  ///< a whole number, with a range
  Flag,    ///< true | false
  Choice,  ///< one of the names in `range` ("hold|retreat"), stored as its index
  Text,    ///< a string
  Names,   ///< a list of strings
  Triple,  ///< a list of three finite numbers
  Vector,  ///< numbers named by `labels` ("x|y|z"): a list of all, or a mapping over some
  Custom   ///< read and checked by the block's own code; declared for its key, its table row
};

/// The member a field fills, as a function of the struct (a captureless
/// lambda; TACTILE_SCHEMA_REF writes one). One accessor serves the reader,
/// which writes, and the checks and tables, which only read (through a
/// const_cast of the struct they were given as const).
template <class S, class T>
using Ref = T& (*)(S&);

/// `[](S& s) -> auto& { return s.member; }`: the accessor of a Field.
#define TACTILE_SCHEMA_REF(S, member) [](S& s_) -> auto& { return s_.member; }
/// `[](S& s) { return s.member.data(); }`: the accessor of a Vector Field.
#define TACTILE_SCHEMA_VEC(S, member) [](S& s_) { return s_.member.data(); }

template <class S>
struct Field {
  const char* key = "";    ///< the key in the block; "a.b" for key b of the mapping a
  Kind kind = Kind::Number;
  const char* unit = "";   ///< the file's unit ("" dimensionless)
  const char* range = "";  ///< Number: the valid range; Choice: the names, '|'-separated
  const char* doc = "";    ///< one line: what the value does
  Ref<S, double> number = nullptr;
  Ref<S, int> integer = nullptr;
  double mul = 1.0, div = 1.0;  ///< member = file value * mul / div
  Ref<S, bool> flag = nullptr;
  int (*get)(const S&) = nullptr;  ///< Choice: the index of the current name
  void (*set)(S&, int) = nullptr;  ///< Choice: store the name of that index
  Ref<S, std::string> text = nullptr;
  Ref<S, std::vector<std::string>> names = nullptr;
  Ref<S, std::array<double, 3>> triple = nullptr;
  double* (*vec)(S&) = nullptr;  ///< Vector: its first entry
  const char* labels = "";       ///< Vector: the entries' names, '|'-separated
  const char* shown = "";        ///< Custom: the default as the table shows it
  /// The variants of the block (its `selector` Choice) the key belongs to,
  /// '|'-separated; "" = every variant. A key given for another variant is
  /// an error, and its range is checked only for its own.
  const char* when = "";
  bool required = false;  ///< the key must be given (for its variants)

  static Field num(const char* key, const char* unit, const char* range, Ref<S, double> ref, const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Number, f.unit = unit, f.range = range, f.doc = doc, f.number = ref;
    return f;
  }
  static Field whole(const char* key, const char* unit, const char* range, Ref<S, int> ref, const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Integer, f.unit = unit, f.range = range, f.doc = doc, f.integer = ref;
    return f;
  }
  /// Degrees in the file (unit "deg" or "deg/s"), radians in the struct.
  static Field deg(const char* key, const char* unit, const char* range, Ref<S, double> ref, const char* doc) {
    Field f = num(key, unit, range, ref, doc);
    f.mul = 3.14159265358979323846, f.div = 180.0;
    return f;
  }
  static Field yesNo(const char* key, Ref<S, bool> ref, const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Flag, f.doc = doc, f.flag = ref;
    return f;
  }
  static Field choice(const char* key, const char* names, int (*get)(const S&), void (*set)(S&, int),
                      const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Choice, f.range = names, f.doc = doc, f.get = get, f.set = set;
    return f;
  }
  static Field str(const char* key, Ref<S, std::string> ref, const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Text, f.doc = doc, f.text = ref;
    return f;
  }
  static Field list(const char* key, Ref<S, std::vector<std::string>> ref, const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Names, f.doc = doc, f.names = ref;
    return f;
  }
  static Field xyz(const char* key, const char* unit, Ref<S, std::array<double, 3>> ref, const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Triple, f.unit = unit, f.doc = doc, f.triple = ref;
    return f;
  }

  /// Numbers named by `labels`, each in `range` ("x|y|z|wx|wy|wz").
  static Field vector(const char* key, const char* unit, const char* labels, const char* range, double* (*ref)(S&),
                      const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Vector, f.unit = unit, f.labels = labels, f.range = range, f.doc = doc, f.vec = ref;
    return f;
  }
  /// A key the block's own code reads and checks: `valid` and `shown` are the
  /// table's text for its form and its default.
  static Field custom(const char* key, const char* unit, const char* valid, const char* shown, const char* doc) {
    Field f;
    f.key = key, f.kind = Kind::Custom, f.unit = unit, f.range = valid, f.shown = shown, f.doc = doc;
    return f;
  }
  /// This field for the variants `variants` of the block's selector only.
  Field only(const char* variants) const {
    Field f = *this;
    f.when = variants;
    return f;
  }
  /// A Text field's form as the table shows it ("a path, relative to the
  /// scene"); the default form is "a name".
  Field form(const char* shown_as) const {
    Field f = *this;
    f.range = shown_as;
    return f;
  }
  /// This field must be given (for its variants).
  Field needed() const {
    Field f = *this;
    f.required = true;
    return f;
  }

  /// The number of entries of a Vector.
  int size() const {
    int n = 1;
    for (const char* c = labels; *c; ++c) n += *c == '|';
    return n;
  }

  /// The number in the file's unit (Number and Integer).
  double value(const S& s) const {
    return kind == Kind::Integer ? integer(const_cast<S&>(s)) : number(const_cast<S&>(s)) * div / mul;
  }
  void store(S& s, double file_value) const {
    if (kind == Kind::Integer) integer(s) = static_cast<int>(file_value);
    else number(s) = file_value * mul / div;
  }
};

/// The declaration of one YAML block over the struct S it fills.
template <class S>
struct Block {
  const char* name = "";  ///< its key in the file ("speed_law")
  const char* doc = "";   ///< one line: what the block is, where it is defined
  std::vector<Field<S>> fields;
  /// The key of the Choice that selects the block's variant (a transition's
  /// `on`); "" = one variant. Fields name theirs in Field::when.
  const char* selector = "";
};

// ---- ranges --------------------------------------------------------------

/// One end of a range: absent, a number, or the value of another key.
struct Limit {
  bool given = false;
  bool open = false;
  double value = 0.0;
  std::string key;  ///< non-empty: the value of this key of the block
};

struct Range {
  Limit lo, hi;
};

namespace detail {

inline std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(' ');
  const std::size_t b = s.find_last_not_of(' ');
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

/// A number ("1e4", "-inf", "inf"; an infinite end is absent) or a key name.
inline bool parseEnd(const std::string& token, bool open, Limit& out) {
  const std::string t = trim(token);
  if (t.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  out.open = open;
  if (end && *end == '\0') {
    out.given = std::isfinite(v);
    out.value = v;
    return true;
  }
  for (char c : t)
    if (!(c == '_' || c == '.' || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'))) return false;
  out.given = true;
  out.key = t;
  return true;
}

}  // namespace detail

/// Parses a range as written in a Field ("(0, 1]", "[0, v_max)", ">= 0",
/// "> 0", ""); false for anything else (a declaration's error: ctest
/// SchemaBlocks checks every shipped one).
inline bool parseRange(const std::string& spec, Range& out) {
  out = Range{};
  const std::string s = detail::trim(spec);
  if (s.empty()) return true;
  if (s.rfind(">=", 0) == 0) return detail::parseEnd(s.substr(2), false, out.lo);
  if (s[0] == '>') return detail::parseEnd(s.substr(1), true, out.lo);
  if (s.size() < 5 || (s[0] != '(' && s[0] != '[') || (s.back() != ')' && s.back() != ']')) return false;
  const std::size_t comma = s.find(',');
  if (comma == std::string::npos) return false;
  return detail::parseEnd(s.substr(1, comma - 1), s[0] == '(', out.lo) &&
         detail::parseEnd(s.substr(comma + 1, s.size() - comma - 2), s.back() == ')', out.hi);
}

template <class S>
const Field<S>* find(const Block<S>& b, const std::string& key) {
  for (const Field<S>& f : b.fields)
    if (key == f.key) return &f;
  return nullptr;
}

namespace detail {

template <class S>
bool limitValue(const Block<S>& b, const S& s, const Limit& l, double& v) {
  if (l.key.empty()) {
    v = l.value;
    return true;
  }
  const Field<S>* f = find(b, l.key);
  if (!f || (f->kind != Kind::Number && f->kind != Kind::Integer)) return false;
  v = f->value(s);
  return true;
}

inline std::string requirement(const char* range, const char* unit) {
  const std::string r = trim(range);
  std::string msg = r.empty() ? "must be finite" : r[0] == '>' ? "must be " + r : "must be in " + r;
  if (unit && *unit) msg += std::string(" ") + unit;
  return msg;
}

template <class S>
ConfigResult checkNumber(const Block<S>& b, const Field<S>& f, double v, const S& s, const std::string& at) {
  Range r;
  double lo = 0.0, hi = 0.0;
  if (!parseRange(f.range, r) || !limitValue(b, s, r.lo, lo) || !limitValue(b, s, r.hi, hi))
    return ConfigResult::failure(at + ": the declaration's range '" + f.range + "' cannot be read");
  bool ok = std::isfinite(v);
  if (ok && r.lo.given) ok = r.lo.open ? v > lo : v >= lo;
  if (ok && r.hi.given) ok = r.hi.open ? v < hi : v <= hi;
  return ok ? ConfigResult::success() : rangeError(at, v, requirement(f.range, f.unit));
}

inline int choiceCount(const char* names) {
  int n = 1;
  for (const char* c = names; *c; ++c) n += *c == '|';
  return n;
}

inline std::string rangeText(Kind k, const char* range);

/// The name at `index` of a '|'-separated list ("?" past its end).
inline std::string choiceName(const char* names, int index) {
  const std::string all(names);
  std::size_t start = 0;
  for (int i = 0;; ++i) {
    const std::size_t bar = all.find('|', start);
    if (i == index) return all.substr(start, bar == std::string::npos ? std::string::npos : bar - start);
    if (bar == std::string::npos) return "?";
    start = bar + 1;
  }
}

inline bool inList(const char* names, const std::string& name) {
  for (int i = 0; i < choiceCount(names); ++i)
    if (choiceName(names, i) == name) return true;
  return false;
}

}  // namespace detail

/// The name of the block's current variant (its selector's choice); "" for
/// a block of one variant.
template <class S>
std::string variant(const Block<S>& b, const S& s) {
  const Field<S>* sel = *b.selector ? find(b, b.selector) : nullptr;
  return sel && sel->kind == Kind::Choice ? detail::choiceName(sel->range, sel->get(s)) : std::string();
}

/// Whether the field belongs to the variant `name` (every field of a block
/// of one variant does).
template <class S>
bool applies(const Field<S>& f, const std::string& name) {
  return !*f.when || detail::inList(f.when, name);
}

/// "'a', 'b' and 'c'": the variants of a '|'-list, for messages.
inline std::string quotedList(const char* names) {
  std::string out;
  const int n = detail::choiceCount(names);
  for (int i = 0; i < n; ++i)
    out += (i == 0 ? "" : i + 1 == n ? " and " : ", ") + ("'" + detail::choiceName(names, i) + "'");
  return out;
}

/// Every Number, Integer, Vector, Triple and Choice of `s` against its
/// declaration (a field of another variant is skipped): the first one out of
/// range fails with "<where>.<key> = <value>: must be in <range> <unit>" (the
/// value in the file's unit; "<key>.<label>" for a Vector's entry). `where`
/// is "<file>: <block>", or "<file>: " for the keys of a file's top level.
template <class S>
ConfigResult checkRanges(const Block<S>& b, const S& s, const std::string& where) {
  const std::string var = variant(b, s);
  const bool top = where.empty() || where.back() == ' ';  // "<file>: ": a file's top level
  for (const Field<S>& f : b.fields) {
    if (!applies(f, var)) continue;
    const std::string at = top ? where + f.key : where + "." + f.key;
    if (f.kind == Kind::Vector) {
      const double* v = f.vec(const_cast<S&>(s));
      for (int i = 0; i < f.size(); ++i) {
        const ConfigResult r = detail::checkNumber(b, f, v[i], s, at + "." + detail::choiceName(f.labels, i));
        if (!r) return r;
      }
    } else if (f.kind == Kind::Number || f.kind == Kind::Integer) {
      const ConfigResult r = detail::checkNumber(b, f, f.value(s), s, at);
      if (!r) return r;
    } else if (f.kind == Kind::Triple) {
      for (double v : f.triple(const_cast<S&>(s)))
        if (!std::isfinite(v)) return rangeError(at, v, "every entry must be finite");
    } else if (f.kind == Kind::Choice) {
      const int i = f.get(s);
      if (i < 0 || i >= detail::choiceCount(f.range))
        return rangeError(at, i, "must be one of " + detail::rangeText(f.kind, f.range));
    }
  }
  return ConfigResult::success();
}

// ---- the docs' tables ----------------------------------------------------

namespace detail {

inline std::string number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

template <class S>
std::string defaultText(const Field<S>& f, const S& d) {
  S& m = const_cast<S&>(d);
  switch (f.kind) {
    case Kind::Number:
    case Kind::Integer: return number(f.value(d));
    case Kind::Flag: return f.flag(m) ? "true" : "false";
    case Kind::Choice: {
      const std::string n = choiceName(f.range, f.get(d));
      return n.empty() ? "''" : n;
    }
    case Kind::Text: return f.text(m).empty() ? "''" : f.text(m);
    case Kind::Names: {
      std::string s = "[";
      for (const std::string& n : f.names(m)) s += (s.size() > 1 ? ", " : "") + n;
      return s + "]";
    }
    case Kind::Triple: {
      const auto& t = f.triple(m);
      return "[" + number(t[0]) + ", " + number(t[1]) + ", " + number(t[2]) + "]";
    }
    case Kind::Vector: {
      const double* v = f.vec(m);
      std::string s = "[";
      for (int i = 0; i < f.size(); ++i) s += (i ? ", " : "") + number(v[i]);
      return s + "]";
    }
    case Kind::Custom: return f.shown;
  }
  return "";
}

inline std::string rangeText(Kind k, const char* range) {
  switch (k) {
    case Kind::Number:
    case Kind::Integer: return *range ? range : "finite";
    case Kind::Flag: return "true, false";
    case Kind::Choice: {  // an empty name (a choice of "nothing given") shows as ''
      std::string out;
      for (int i = 0; i < choiceCount(range); ++i) {
        const std::string n = choiceName(range, i);
        out += (i ? ", " : "") + (n.empty() ? std::string("''") : n);
      }
      return out;
    }
    case Kind::Text: return *range ? range : "a name";
    case Kind::Names: return "a list of names";
    case Kind::Triple: return "3 finite numbers";
    case Kind::Vector: return "";  // vectorText
    case Kind::Custom: return range;
  }
  return "";
}

template <class S>
std::string validText(const Field<S>& f) {
  if (f.kind != Kind::Vector) return rangeText(f.kind, f.range);
  std::string names;
  for (int i = 0; i < f.size(); ++i) names += (i ? ", " : "") + choiceName(f.labels, i);
  return "each " + rangeText(Kind::Number, f.range) + "; a list of " + std::to_string(f.size()) +
         " or a mapping over " + names;
}

/// The table's "valid" cell: the range, then the variants and whether the
/// key must be given.
template <class S>
std::string validCell(const Field<S>& f) {
  std::string v = validText(f);
  if (*f.when) v += (v.empty() ? "" : "; ") + std::string("only for ") + quotedList(f.when);
  if (f.required) v += (v.empty() ? "" : "; ") + std::string("required");
  return v;
}

}  // namespace detail

/// The block's key table (Markdown): key, unit, range or choices, default,
/// meaning; the defaults are those of a default-constructed S.
template <class S>
std::string markdownTable(const Block<S>& b, const std::string& prefix = "") {
  const S d{};
  std::string t = "| key | unit | valid | default | what it does |\n|---|---|---|---|---|\n";
  for (const Field<S>& f : b.fields)
    t += "| `" + prefix + f.key + "` | " + (*f.unit ? f.unit : "") + " | " + detail::validCell(f) +
         " | " + detail::defaultText(f, d) + " | " + f.doc + " |\n";
  return t;
}

/// A block's section of the docs: "#### `name`", its meaning, its table.
template <class S>
std::string markdownSection(const Block<S>& b) {
  std::string doc = b.doc;
  if (!doc.empty() && doc[0] >= 'a' && doc[0] <= 'z') doc[0] = static_cast<char>(doc[0] - 'a' + 'A');
  return std::string("#### `") + b.name + "`\n\n" + doc + ".\n\n" + markdownTable(b);
}

}  // namespace schema
}  // namespace tactile
