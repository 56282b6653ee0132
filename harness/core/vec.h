// Small fixed-size vectors, generic over the scalar so methods run in float and double.
#pragma once
#include <cmath>

namespace pxh {

template <typename T>
struct Vec2 {
    T x{}, y{};
    constexpr Vec2() = default;
    constexpr Vec2(T x_, T y_) : x(x_), y(y_) {}
    template <typename U>
    constexpr explicit Vec2(const Vec2<U>& o) : x(T(o.x)), y(T(o.y)) {}
    constexpr Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
    constexpr Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
    constexpr Vec2 operator*(T k) const { return {x * k, y * k}; }
    constexpr Vec2& operator+=(Vec2 o) {
        x += o.x;
        y += o.y;
        return *this;
    }
};
template <typename T>
constexpr Vec2<T> operator*(T k, Vec2<T> v) {
    return {k * v.x, k * v.y};
}

template <typename T>
struct Vec3 {
    T x{}, y{}, z{};
    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    template <typename U>
    constexpr explicit Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
    constexpr Vec2<T> xy() const { return {x, y}; }
};

using Vec2d = Vec2<double>;
using Vec3d = Vec3<double>;

}  // namespace pxh
