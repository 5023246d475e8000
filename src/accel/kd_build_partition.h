// Splitting one kd-tree node: classification of its triangles, perfect-split clipping of
// the straddling ones, the children's ref lists and (for SAH) their spliced event lists.
#pragma once

#include "accel/kd_build_types.h"

namespace lancer::kd {

// Splits `in` at `choice` into `left` and `right` (Wald & Havran 2006, section 4.3):
// a ref lying in the plane goes to choice.planar; one ending at the plane goes left, one
// starting at it goes right; one straddling it is clipped to both child cells and kept
// on each side where the clipped triangle is not empty. Children get a share of the
// reference budget proportional to their ref counts. Returns false, leaving `in` as it
// was, when the children together would hold more references than `in.budget`; else
// hands the vectors of `in` to `scratch` for reuse (leaving `in` empty) and returns true.
// `scratch` holds the temporaries and supplies the children's vectors. `big` (a big node)
// splices events into the left child only, freeing its own axis by axis before the
// children's refs are made, writes the left refs over its own, and gives the right child
// refs only: it sorts its own events when it starts (the bound on peak memory, see
// kd_build.cpp). `threads`: many straddling triangles are clipped in parallel.
bool partition_node(const TriangleSoA& tris, NodeInput& in, const SplitChoice& choice, bool big, bool threads,
                    NodeInput& left, NodeInput& right, BuildScratch& scratch);

}  // namespace lancer::kd
