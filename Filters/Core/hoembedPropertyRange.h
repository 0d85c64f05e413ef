/**
 * @file hoembedPropertyRange.h
 * @brief The valid range of a driver's numeric property and the one sentence that refuses
 *        a value outside it (plain C++, VTK-free).
 *
 * Each driver states its properties' ranges once, next to its options struct (e.g.
 * hoembed::MesherRanges), and checks its options with them; the VTK filters, the
 * nanobind module (RANGES, check_range) and the ParaView XML's range domains (a test
 * keeps them inside) read those tables instead of writing the limits again.
 */
#ifndef hoembedPropertyRange_h
#define hoembedPropertyRange_h

#include <limits>
#include <sstream>
#include <string>

namespace hoembed
{
/// An upper or lower bound that is no bound (the printed range then has one side only).
constexpr double NoLimit = std::numeric_limits<double>::max();

/// [Min, Max] (each end open when MinOpen / MaxOpen), integers only when Integer.
struct PropertyRange
{
  const char* Name;
  double Min;
  double Max;
  bool MinOpen;
  bool MaxOpen;
  bool Integer;
};

/// "" when `value` lies in `r` (NaN never does), else "<Name> must be <range> (got v)."
inline std::string CheckPropertyRange(const PropertyRange& r, double value)
{
  const bool aboveMin = r.MinOpen ? value > r.Min : value >= r.Min;
  const bool belowMax = r.MaxOpen ? value < r.Max : value <= r.Max;
  // (an integer property's value arrives as an exact double; a fraction is refused)
  const bool whole = !r.Integer || static_cast<double>(static_cast<long long>(value)) == value;
  if (aboveMin && belowMax && whole)
    return std::string();
  std::ostringstream o;
  o.precision(15);
  o << r.Name << " must be ";
  if (r.Integer)
    o << "an integer ";
  if (r.Min == -NoLimit && r.Max == NoLimit)
    o << "finite";
  else if (r.Max == NoLimit)
    o << (r.MinOpen ? "> " : ">= ") << r.Min;
  else if (r.Min == -NoLimit)
    o << (r.MaxOpen ? "< " : "<= ") << r.Max;
  else
    o << "in " << (r.MinOpen ? '(' : '[') << r.Min << ", " << r.Max << (r.MaxOpen ? ')' : ']');
  o << " (got " << value << ").";
  return o.str();
}

/// The range named `name` in `table` (nullptr when absent).
template <std::size_t N>
const PropertyRange* FindPropertyRange(const PropertyRange (&table)[N], const std::string& name)
{
  for (const PropertyRange& r : table)
  {
    if (name == r.Name)
      return &r;
  }
  return nullptr;
}
} // namespace hoembed

#endif
