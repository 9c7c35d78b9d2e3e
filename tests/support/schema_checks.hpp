// Checks of a declared parameter block (tactile_types/schema.hpp), shared by
// the tests of every block: each range readable and enforced with its
// message, the defaults inside their ranges, each key declared once (or
// once per variant) with a meaning.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "tactile_types/schema.hpp"

namespace tactile {
namespace test {

using schema::Block;
using schema::Kind;

/// The ends of a field's range at the values of `s` (an end may name another key).
template <class S>
void ends(const Block<S>& b, const schema::Field<S>& f, const S& s, schema::Range& r, double& lo, double& hi) {
  ASSERT_TRUE(schema::parseRange(f.range, r)) << b.name << "." << f.key << ": '" << f.range << "'";
  lo = r.lo.given ? (r.lo.key.empty() ? r.lo.value : schema::find(b, r.lo.key)->value(s)) : 0.0;
  hi = r.hi.given ? (r.hi.key.empty() ? r.hi.value : schema::find(b, r.hi.key)->value(s)) : lo + 2.0;
}

/// `d` in the variant of `f` (its first), with every Number of that variant
/// that must be given set inside its range: a state where only `f` decides.
template <class S>
S variantOf(const Block<S>& b, const schema::Field<S>& f, const S& d) {
  S s = d;
  if (!*f.when) return s;
  const auto* sel = schema::find(b, b.selector);
  const std::string name = schema::detail::choiceName(f.when, 0);
  for (int i = 0; i < schema::detail::choiceCount(sel->range); ++i)
    if (schema::detail::choiceName(sel->range, i) == name) sel->set(s, i);
  for (const auto& g : b.fields)
    if (g.kind == Kind::Number && g.required && schema::applies(g, name)) {
      schema::Range r;
      double lo = 0.0, hi = 0.0;
      ends(b, g, s, r, lo, hi);
      g.store(s, 0.5 * (lo + hi));
    }
  return s;
}

/// Every Number, Integer and Vector with a numeric end: just outside that end (or
/// NaN) is refused, in the field's own variant, naming "<where>.<key> = "
/// and the declared range. The defaults lie within the ranges.
template <class S>
void expectRangesEnforced(const Block<S>& b) {
  const S d{};
  const std::string where = "f.yaml: " + std::string(b.name);
  ASSERT_TRUE(schema::checkRanges(b, d, where).ok())
      << b.name << ": the defaults lie outside their ranges: " << schema::checkRanges(b, d, where).message();
  for (const auto& f : b.fields) {
    if (f.kind != Kind::Number && f.kind != Kind::Integer && f.kind != Kind::Vector) continue;
    const S base = variantOf(b, f, d);
    ASSERT_TRUE(schema::checkRanges(b, base, where).ok()) << schema::checkRanges(b, base, where).message();
    const std::string key = f.kind == Kind::Vector ? std::string(f.key) + "." + schema::detail::choiceName(f.labels, 0)
                                                   : std::string(f.key);
    const std::string at = where + "." + key + " = ";
    auto refuse = [&](double v, const char* why) {
      S s = base;
      if (f.kind == Kind::Vector) f.vec(s)[0] = v;
      else f.store(s, v);
      const ConfigResult c = schema::checkRanges(b, s, where);
      ASSERT_FALSE(c.ok()) << b.name << "." << key << " = " << v << " (" << why << ") accepted";
      EXPECT_NE(c.message().find(at), std::string::npos) << c.message();
      EXPECT_NE(c.message().find(f.range), std::string::npos) << c.message();
    };
    if (f.kind != Kind::Integer) refuse(std::nan(""), "NaN");
    schema::Range r;
    double lo = 0.0, hi = 0.0;
    ends(b, f, base, r, lo, hi);
    const double step =
        f.kind == Kind::Integer ? 1.0 : 1e-9 * std::max(1.0, std::max(std::fabs(lo), std::fabs(hi)));
    if (r.lo.given) refuse(r.lo.open ? lo : lo - step, "below its lower end");
    if (r.hi.given) refuse(r.hi.open ? hi : hi + step, "above its upper end");
  }
}

/// Each key declared once, or once per variant (disjoint `when`s), each with a meaning.
template <class S>
void expectKeysUniqueAndDocumented(const Block<S>& b) {
  for (std::size_t i = 0; i < b.fields.size(); ++i) {
    const auto& f = b.fields[i];
    EXPECT_GT(std::string(f.doc).size(), 8u) << b.name << "." << f.key << ": no meaning";
    for (std::size_t j = i + 1; j < b.fields.size(); ++j) {
      const auto& g = b.fields[j];
      if (std::string(f.key) != g.key) continue;
      bool overlap = !*f.when || !*g.when;
      for (int k = 0; !overlap && k < schema::detail::choiceCount(g.when); ++k)
        overlap = schema::detail::inList(f.when, schema::detail::choiceName(g.when, k));
      EXPECT_FALSE(overlap) << b.name << "." << f.key << ": declared twice for one variant";
    }
  }
}

}  // namespace test
}  // namespace tactile
