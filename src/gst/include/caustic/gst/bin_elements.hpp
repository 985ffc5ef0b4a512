// SPDX-License-Identifier: LGPL-2.1-or-later
// A bin's elements, picked and held: GstIterator asks its caller to start
// again whenever the bin changes under the walk (a resync), and a caller
// that stops or changes what it found must not do so while walking.
#pragma once

#include <gst/gst.h>

#include <functional>
#include <vector>

namespace caustic::gst {

/// The elements inside `bin` (at any depth when `recurse`, else its
/// children) for which `keep` is true, each a new reference that the
/// caller unrefs. Empty when `bin` is null or not a bin. An iterator error
/// ends the walk with what was found.
std::vector<GstElement*> bin_elements(GstElement* bin, bool recurse, const std::function<bool(GstElement*)>& keep);

}  // namespace caustic::gst
