#pragma once
// The gravitational acceleration every part of the library uses: the weight m g the support carries, and so the
// friction force mu m g (the value the dataset's own tooling uses).
namespace pushpred {

inline constexpr double kGravity_m_s2 = 9.81;  ///< g [m/s^2]

}  // namespace pushpred
