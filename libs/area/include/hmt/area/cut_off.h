// Whether scans just taken are cut off from an area's keyframes by the area
// abstraction's own criterion.
//
// TSBI's area check (tsbi::TransitionModel::same_area): a known area is a
// candidate of a new-area event only if the latest scans, placed at the
// match, would not be split from its keyframes: the Ncut of their SSO
// graph between the two sets is at least tau (001, Eq. 14-15: below tau
// the partitioner would cut there).
//
// Computed with fewer scan matches than the whole graph takes: the pairs
// within each set first (the keyframes' through a cache that lasts from
// event to event), then the latest scans' pairs with the keyframes one
// latest scan at a time. With the weights within each set fixed, the Ncut
// cut/assoc(A) + cut/assoc(B) = c/(a + c) + c/(b + c) only grows with the
// cut c, so once the pairs so far reach tau (by a margin far above the
// rounding of summing in another order) the rest need not be matched.
// Otherwise the whole graph's Ncut decides, as before. Either way the
// answer is normalized_cut(whole graph) < tau's (tested).
#pragma once

#include <memory>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/keyframe.h"
#include "hmt/area/sso_pair_cache.h"

namespace hmt::area {

// True when Ncut(latest | keyframes) < tau over the SSO graph of both
// (options.sso, min_sso). Empty `keyframes` or `latest`: false (nothing
// to cut). `keyframe_pairs`, if given, holds the keyframes' pairs between
// calls (the latest scans' are new at every call and are not put there).
// `latest_matched`, if given: how many of the latest scans were matched
// against the keyframes before the answer was known.
bool cut_off(const std::vector<Keyframe>& keyframes, const std::vector<Keyframe>& latest,
             const AreaOptions& options, double tau,
             const std::shared_ptr<SsoPairCache>& keyframe_pairs = nullptr,
             size_t* latest_matched = nullptr);

}  // namespace hmt::area
