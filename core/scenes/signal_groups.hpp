// Groups of signals that several scenes record, defined once, and `concat`, which joins groups
// and single signals into a scene's signal list at compile time:
//   constexpr auto kSignals = concat(SignalId::time, kBallMotion, kContactSignals, kEnergyAudit);
// The ORDER of a scene's list matters: with `signals: "all"` (the default) a study records the
// list as it stands, and CaseSpec::canonical() hashes it into the case id. A group below keeps
// the order the scenes had before it was factored out; a change of order changes case ids.
#pragma once

#include <array>
#include <cstddef>
#include <type_traits>

#include "core/signals.hpp"

namespace rodend {

namespace detail {
template <class T>
struct signal_group_size;
template <>
struct signal_group_size<SignalId> : std::integral_constant<std::size_t, 1> {};
template <std::size_t N>
struct signal_group_size<std::array<SignalId, N>> : std::integral_constant<std::size_t, N> {};
}  // namespace detail

/// The groups and single signals, in the order given, as one std::array.
template <class... Groups>
constexpr auto concat(const Groups&... groups) {
  std::array<SignalId, (detail::signal_group_size<Groups>::value + ... + 0)> list{};
  std::size_t n = 0;
  const auto append = [&](const auto& g) {
    if constexpr (std::is_same_v<std::decay_t<decltype(g)>, SignalId>)
      list[n++] = g;
    else
      for (SignalId id : g) list[n++] = id;
  };
  (append(groups), ...);
  return list;
}

/// True when no signal stands twice in `list` (a scene lists each signal once).
template <std::size_t N>
constexpr bool distinct(const std::array<SignalId, N>& list) {
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = i + 1; j < N; ++j)
      if (list[i] == list[j]) return false;
  return true;
}

/// The ball's (inner body's) motion: position, velocity, angular velocity.
inline constexpr std::array kBallMotion{SignalId::ball_position, SignalId::ball_velocity,
                                        SignalId::ball_angular_velocity};
/// The socket's (outer body's) motion: position, velocity, angular velocity.
inline constexpr std::array kSocketMotion{SignalId::socket_position, SignalId::socket_velocity,
                                          SignalId::socket_angular_velocity};
/// Both spheres free: each one's motion followed by its Euler 3-2-1 angles.
inline constexpr auto kBallAndSocket =
    concat(kBallMotion, SignalId::ball_euler_321, kSocketMotion, SignalId::socket_euler_321);

/// Where the ball sits in the socket (the first contact signals).
inline constexpr std::array kContactPlacement{SignalId::eccentricity_vector, SignalId::eccentricity,
                                              SignalId::relative_position};
/// What the contact does: penetration, forces, slip, wear indicator, contact angle.
inline constexpr std::array kContactResponse{
    SignalId::penetration,          SignalId::penetration_rate, SignalId::impact_speed,
    SignalId::contact_force_vector, SignalId::contact_force,    SignalId::friction_force_vector,
    SignalId::friction_force,       SignalId::slip_speed,       SignalId::wear_indicator,
    SignalId::contact_angle};
/// The signals write_contact_signals (parts.hpp) writes, in catalogue order.
inline constexpr auto kContactSignals = concat(kContactPlacement, kContactResponse);

/// The signals write_energy_signals (parts.hpp) writes.
inline constexpr std::array kEnergySignals{SignalId::mechanical_energy, SignalId::input_work,
                                           SignalId::dissipated_energy, SignalId::energy_residual};
/// The energy audit of a scene that also writes its kinetic energy.
inline constexpr auto kEnergyAudit = concat(SignalId::kinetic_energy, kEnergySignals);
/// The energy audit of a scene of 6-DOF bodies, then the drift of their quaternions' norm.
inline constexpr auto kBodyAudit = concat(kEnergyAudit, SignalId::quaternion_norm_error);

/// The servo loop of the actuator (ServoActuator::outputs) between its command and its rod:
/// LVDT, controller current, jet pipe, spool, chambers, external force, hydraulic power.
inline constexpr std::array kServoLoopSignals{
    SignalId::lvdt_position,           SignalId::controller_current, SignalId::jet_pipe_position,
    SignalId::spool_position,          SignalId::chamber_pressures,  SignalId::chamber_flows,
    SignalId::actuator_external_force, SignalId::hydraulic_power};

}  // namespace rodend
