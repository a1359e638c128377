#pragma once
// Structural checks of OctoMap .ot and .bt bodies before liboctomap reads them.
//
// liboctomap reads both node streams recursively and keeps reading after the stream has ended: a truncated or forged
// body then descends on bytes it never read (an uninitialised child mask), without a depth bound, until the thread's
// stack overflows. These checks walk the same streams iteratively, with the tree's depth bound (16) and the body's
// length, so that only a body that decodes whole reaches liboctomap.
#include <string_view>

namespace anchordb::engine {

// The node bytes of an OcTree .ot body (what follows its header's `data` line, found by liboctomap's own header
// reader): per node a 4-byte log-odds value and a child mask. Throws Error(kInvalidArgument, field "body") naming what
// is wrong.
void CheckOtNodeStream(std::string_view node_bytes);

// The node bytes of an OcTree .bt body whose header gives a size above 0: per inner node two bytes holding 2 bits per
// child.
void CheckBtNodeStream(std::string_view node_bytes);

}  // namespace anchordb::engine
