// Quantities with units in case files: "4 mm", "30 Hz", "200 GPa", "7.8 g/cm^3", "9.81 m/s^2".
// A plain number is SI. Everything inside bagdem is SI; conversion happens here and only here.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace bagdem {

// Physical dimension as integer exponents of (m, kg, s, rad).
struct Dimension {
  int length = 0, mass = 0, time = 0, angle = 0;
  bool operator==(const Dimension&) const = default;
  std::string si_unit() const;  // e.g. "kg/m^3", "m/s^2", "1" for dimensionless
};

namespace dim {
inline constexpr Dimension none{};
inline constexpr Dimension length{1, 0, 0, 0};
inline constexpr Dimension mass{0, 1, 0, 0};
inline constexpr Dimension time{0, 0, 1, 0};
inline constexpr Dimension angle{0, 0, 0, 1};
inline constexpr Dimension frequency{0, 0, -1, 0};
inline constexpr Dimension speed{1, 0, -1, 0};
inline constexpr Dimension acceleration{1, 0, -2, 0};
inline constexpr Dimension density{-3, 1, 0, 0};
inline constexpr Dimension pressure{-1, 1, -2, 0};  // Pa = kg/(m s^2)
inline constexpr Dimension force{1, 1, -2, 0};
inline constexpr Dimension energy{2, 1, -2, 0};
inline constexpr Dimension stiffness{0, 1, -2, 0};  // N/m
inline constexpr Dimension damping{0, 1, -1, 0};    // N s/m
inline constexpr Dimension area_moment{4, 0, 0, 0}; // second moment of area, m^4
inline constexpr Dimension line_density{-1, 1, 0, 0};  // kg/m
inline constexpr Dimension inertia{2, 1, 0, 0};     // kg m^2
inline constexpr Dimension impulse{1, 1, -1, 0};    // N s
}  // namespace dim

// Parses "<number> [unit expression]" into an SI value of the expected dimension.
// Unit expressions: products and quotients of units with optional integer powers,
// e.g. "kg/m^3", "N*m", "m s^-2", "g/cm^3", "1/s". Known units (with SI prefixes n, u, µ, m, c, k, M, G
// where sensible): m, g, s, min, h, Hz, rad, deg, rev (angle), N, Pa, J, W, bar, and "%" (0.01).
// Angles: "rad" is the SI angle; frequency in Hz is cycles/s and is dimension 1/s (not rad/s).
// On error returns std::nullopt and sets *why to a short reason ("unknown unit 'mmm'",
// "dimension m/s, expected m"), if why is not null.
std::optional<double> parse_quantity(std::string_view text, Dimension expected,
                                     std::string* why = nullptr);

// The same, for a quantity of whatever dimension its unit has (a plain number: has_unit false).
struct Quantity {
  double si;
  Dimension dim;
  bool has_unit;
};
std::optional<Quantity> parse_any_quantity(std::string_view text, std::string* why = nullptr);

}  // namespace bagdem
