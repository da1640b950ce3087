// Integer division rounded down or up, for any signs (C++'s `/` truncates
// towards zero, which puts negative cell and tile coordinates in the wrong
// block).
#pragma once

#include <type_traits>

namespace hmt {

template <class T>
constexpr T floor_div(T a, T b) {
  static_assert(std::is_integral_v<T> && std::is_signed_v<T>);
  return a / b - static_cast<T>((a % b != 0) && ((a < 0) != (b < 0)));
}

template <class T>
constexpr T ceil_div(T a, T b) {
  return -floor_div<T>(-a, b);
}

}  // namespace hmt
