// How large an area is: the Ncut threshold tau derived from the sensor.
//
// The papers cut the graph of observations while Ncut < tau, with tau = 1 the
// parameter-free choice of 001 Eq. 12-13 (a bisection is accepted once the
// SSO across the two halves is lower than within them). That argument holds
// for a sensor that sees all around. A laser that sees a field of view
// phi < 360 degrees senses only part of a place from any one pose, and two
// scans taken at the same spot facing away from each other share nothing.
// Then a single place -- a room the robot turns around in, a corridor it
// walks down and back -- already splits by heading alone: with tau = 1 and
// a 180 degree laser, areas of 4-5 keyframes (2-3 m of path) on the shared
// logs, one arc of error and one loop-closure candidate each.
//
// The rule. Take one place observed from headings spread uniformly, and
// let the SSO of two scans be the fraction of the field of view they share
// (a scan sees its field of view of the place's walls): for heading
// difference d, overlap(d) = (max(0, phi - d) + max(0, phi - (2 pi - d))) / phi.
// Split the observations into the two heading halves, the cut a spectral
// bisection finds first. Its Ncut, 2c / (a + c) with a the mean overlap
// within a half and c across, is place_ncut(phi): 1 for 360 degrees (no
// heading split: the papers' tau = 1 then keeps a place whole), 2/3 for 180
// degrees. A threshold below place_ncut(phi) never cuts a place by heading
// alone, so the cut must come from the space sensed: a doorway, a corner, a
// corridor leaving the area. tau = kTauMargin * place_ncut(phi): the
// margin because an area's keyframes are few and their headings cluster (the
// robot walks a corridor one way and back), so a heading split scatters
// below its expectation. 3/4 gives tau = 0.5 for 180 degree lasers (every
// shared log: rooms and corridor stretches of 10-20 m, loops closing) and
// 0.75 for 360 degrees; lower margins merge what should be separate places
// (0.4 on 180 degrees doubled parts of the infinite corridor's map).
//
// The SSO must then measure the space, not the sensor's sampling: the
// fixed tolerance delta of 001 Eq. 16 misses points of one wall seen from
// two poses once the beam spacing r * beta exceeds delta (beyond 11 m for 1
// degree beams), so long corridors and outdoor scenes would fall apart by
// range alone. The default configuration therefore uses the probabilistic
// SSO of 000 Eq. 16, whose sigma_f = r * beta follows the beam spacing.
#pragma once

#include "hmt/area/area_options.h"
#include "hmt/common/sensor_data.h"

namespace hmt::area {

constexpr double kTauMargin = 0.75;

// The Ncut of one place split by heading, for a sensor of field of view
// `fov` (radians, in (0, 2 pi]; larger values are taken as 2 pi).
double place_ncut(double fov);

// kTauMargin * place_ncut(fov).
double tau_for_field_of_view(double fov);

// The angular span a scan covers: beams x increment, at most 2 pi (0 for a
// scan with no beams).
double field_of_view(const LaserScan& scan);

// When options.partition.tau_from_sensor is set, sets options.partition.tau
// from the field of view of the first scan of `log` with at least two beams
// and returns true; returns false (tau unchanged) otherwise.
bool resolve_tau(AreaOptions& options, const Log& log);
// The same for one scan: sets tau and returns true if tau_from_sensor is
// set and `scan` has at least two beams and a field of view (a log read
// step by step tries its scans in order until one does).
bool resolve_tau(AreaOptions& options, const LaserScan& scan);

}  // namespace hmt::area
