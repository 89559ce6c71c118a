// Unit conversion for case files. Everything past this file is SI: m, kg, s, rad.
//
// Unit expressions are factors joined by '*', '.', or blanks (product) or '/' (quotient), each an
// optional-prefix unit symbol with an optional integer power: "kg/m^3", "N*m", "m s^-2".
// A '/' divides only the one factor right after it, so "m/s/s" = m s^-2 and "kg/m/s^2" is a pascal.
// "1/s" and "30/s" both mean per second; parentheses are not supported.
#include "bagdem/units.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <utility>

namespace bagdem {
namespace {

constexpr Dimension power{2, 1, -3, 0};  // W = J/s
constexpr int max_exponent = 9;           // larger powers are certainly typos

struct Unit {
  std::string_view symbol;
  double si;          // one of this unit, in SI
  Dimension dim;
  bool takes_prefix;  // n, u, µ, m, c, k, M, G
};

// Mass's SI unit is the kilogram, so the gram is 1e-3 and "kg" is the prefixed gram.
// Hz counts cycles per second and rpm cycles per minute: both are frequencies (1/s), not rad/s.
// Hence "3000 rpm" is 50 (1/s), whereas "3000 rev/min" is an angular speed of 100 pi rad/s.
constexpr Unit units[] = {
    {"m", 1.0, dim::length, true},
    {"g", 1e-3, dim::mass, true},
    {"s", 1.0, dim::time, true},
    {"min", 60.0, dim::time, false},
    {"h", 3600.0, dim::time, false},
    {"Hz", 1.0, dim::frequency, true},
    {"rpm", 1.0 / 60.0, dim::frequency, false},
    {"rad", 1.0, dim::angle, false},
    {"deg", std::numbers::pi / 180.0, dim::angle, false},
    {"rev", 2.0 * std::numbers::pi, dim::angle, false},
    {"N", 1.0, dim::force, true},
    {"Pa", 1.0, dim::pressure, true},
    {"bar", 1e5, dim::pressure, false},
    {"J", 1.0, dim::energy, true},
    {"W", 1.0, power, true},
    {"%", 0.01, dim::none, false},
};

struct Prefix {
  std::string_view symbol;
  double factor;
};

// Micro is "u", the micro sign U+00B5 or the Greek mu U+03BC (both UTF-8 encoded).
constexpr Prefix prefixes[] = {
    {"n", 1e-9}, {"u", 1e-6}, {"\xC2\xB5", 1e-6}, {"\xCE\xBC", 1e-6},
    {"m", 1e-3}, {"c", 1e-2}, {"k", 1e3}, {"M", 1e6}, {"G", 1e9},
};

// A unit raised to a power, or a product of such: SI factor and dimension.
struct Scaled {
  double factor = 1.0;
  Dimension dim;
};

Dimension times(Dimension a, Dimension b, int power_of_b) {
  return {a.length + power_of_b * b.length, a.mass + power_of_b * b.mass,
          a.time + power_of_b * b.time, a.angle + power_of_b * b.angle};
}

std::nullopt_t fail(std::string* why, std::string reason) {
  if (why) *why = std::move(reason);
  return std::nullopt;
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

// Letters, '%', and any non-ASCII byte (so "µm" stays one symbol).
bool is_symbol_char(char c) {
  const auto u = static_cast<unsigned char>(c);
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '%' || u >= 0x80;
}

// Exact unit first, then prefix + unit: "m" metre, "min" minute, "mm" millimetre, "ms" millisecond.
std::optional<Scaled> lookup(std::string_view symbol) {
  for (const Unit& u : units)
    if (u.symbol == symbol) return Scaled{u.si, u.dim};
  for (const Prefix& p : prefixes) {
    if (!symbol.starts_with(p.symbol)) continue;
    const std::string_view base = symbol.substr(p.symbol.size());
    for (const Unit& u : units)
      if (u.takes_prefix && u.symbol == base) return Scaled{p.factor * u.si, u.dim};
  }
  return std::nullopt;
}

// Reads "^<integer>" at s[i] if present; the power is 1 otherwise.
std::optional<int> read_exponent(std::string_view s, size_t& i) {
  if (i >= s.size() || s[i] != '^') return 1;
  ++i;
  if (i < s.size() && s[i] == '+') {
    ++i;
    if (i < s.size() && s[i] == '-') return std::nullopt;  // "^+-2"
  }
  int e = 0;
  const auto [end, ec] = std::from_chars(s.data() + i, s.data() + s.size(), e);
  if (ec != std::errc{} || e > max_exponent || e < -max_exponent) return std::nullopt;
  i = static_cast<size_t>(end - s.data());
  const bool fractional = i + 1 < s.size() && s[i] == '.' && s[i + 1] >= '0' && s[i + 1] <= '9';
  if (fractional) return std::nullopt;  // "m^1.5"
  return e;
}

// Product of the factors in a unit expression such as "g/cm^3".
std::optional<Scaled> parse_units(std::string_view expr, std::string* why) {
  std::string quoted = "'";
  quoted.append(expr).append("'");
  Scaled total;
  size_t i = 0;
  bool first = true;      // no factor read yet
  char pending_op = 0;    // operator still waiting for its factor
  int sign = 1;           // -1 right after '/'
  if (expr.front() == '1') {  // "1/s": the 1 only stands before a '/'
    i = 1;
    while (i < expr.size() && is_blank(expr[i])) ++i;
    if (i == expr.size() || expr[i] != '/') return fail(why, "expected '/' after '1' in " + quoted);
    first = false;
  }
  while (i < expr.size()) {
    const char c = expr[i];
    if (is_blank(c)) {
      ++i;
    } else if (c == '*' || c == '.' || c == '/') {
      if (pending_op || (first && c != '/'))
        return fail(why, std::string("misplaced '") + c + "' in " + quoted);
      pending_op = c;
      sign = c == '/' ? -1 : 1;
      ++i;
    } else {
      const size_t start = i;
      while (i < expr.size() && is_symbol_char(expr[i])) ++i;
      if (i == start) return fail(why, std::string("unexpected character '") + c + "' in " + quoted);
      const std::string_view symbol = expr.substr(start, i - start);
      const std::optional<Scaled> unit = lookup(symbol);
      if (!unit) return fail(why, "unknown unit '" + std::string(symbol) + "'");
      const std::optional<int> e = read_exponent(expr, i);
      if (!e) return fail(why, "bad exponent after '" + std::string(symbol) + "' in " + quoted +
                                   " (integer from -9 to 9 expected)");
      total.factor *= std::pow(unit->factor, sign * *e);
      total.dim = times(total.dim, unit->dim, sign * *e);
      first = false;
      pending_op = 0;
      sign = 1;
    }
  }
  if (pending_op) return fail(why, std::string("missing unit after '") + pending_op + "' in " + quoted);
  return total;
}

// Appends "kg" for e = 1, "kg^2" otherwise.
void append_power(std::string& out, std::string_view symbol, int e) {
  out.append(symbol);
  if (e != 1) out.append("^").append(std::to_string(e));
}

}  // namespace

// Positive powers first, in the order kg m s rad, then each negative power after its own '/';
// the result parses back: pressure is "kg/m/s^2", energy "kg m^2/s^2".
std::string Dimension::si_unit() const {
  const std::pair<std::string_view, int> base[] = {{"kg", mass}, {"m", length}, {"s", time}, {"rad", angle}};
  std::string numerator, denominator;
  for (const auto& [symbol, e] : base) {
    if (e > 0) append_power(numerator.append(numerator.empty() ? "" : " "), symbol, e);
    if (e < 0) append_power(denominator.append("/"), symbol, -e);
  }
  return (numerator.empty() ? "1" : numerator) + denominator;
}

std::optional<Quantity> parse_any_quantity(std::string_view text, std::string* why) {
  const std::string s(trim(text));
  if (s.empty()) return fail(why, "empty quantity");
  char* end = nullptr;
  const double value = std::strtod(s.c_str(), &end);
  if (end == s.c_str()) return fail(why, "no number in '" + s + "'");
  if (!std::isfinite(value)) return fail(why, "not a finite number in '" + s + "'");

  const std::string_view expr = trim(std::string_view(s).substr(static_cast<size_t>(end - s.c_str())));
  if (expr.empty()) return Quantity{value, dim::none, false};

  const std::optional<Scaled> unit = parse_units(expr, why);
  if (!unit) return std::nullopt;
  const double si = value * unit->factor;
  if (!std::isfinite(si)) return fail(why, "'" + s + "' is out of range as a double in SI");
  return Quantity{si, unit->dim, true};
}

std::optional<double> parse_quantity(std::string_view text, Dimension expected, std::string* why) {
  const std::optional<Quantity> q = parse_any_quantity(text, why);
  if (!q) return std::nullopt;
  if (q->has_unit && q->dim != expected)  // plain numbers are SI, whatever the dimension
    return fail(why, "has dimension " + q->dim.si_unit() + ", expected " + expected.si_unit());
  return q->si;
}

}  // namespace bagdem
