// Four candidate pairs at a time: a certified plane rejection ahead of the full triangle pair
// test (triangle_triangle.hpp), for the DCD candidate loop.
//
// Rule (Moller's plane rejection, with shared corners excused): if the corners of Q that are not
// corners of P lie strictly on one side of P's plane, then Q meets that plane only in the hull S
// of the shared corners (they lie on it), so P n Q is inside S and the pair does not collide in
// the sense of triangles_collide; likewise with P and Q swapped. Each sign is the orient3d
// filter of FilteredPlane, bit for bit (same operations, same order, no FMA): a lane is set
// only when the filter proves every sign, so the rule holds exactly. Per pair the block costs
// about a third of a full test (12-16 against 35-39 ns on the candidates of the real steps,
// warm), and settles 85-88% of them there. triangles_collide4, the DCD loop's test, decides most
// lanes it leaves from the signs it proved and the rest with triangles_collide: together they
// answer exactly what triangles_collide alone answers.
#pragma once

#include <cstdint>
#include <utility>

namespace conecull {

using FacePair = std::pair<int32_t, int32_t>;

// Bit l (l < 4) set: pairs[l] is proven not to collide by the rule above. V: positions (n, 3);
// F: faces (m, 3); the four pairs' face ids index F. AVX2 where the CPU has it (checked once),
// else the same arithmetic one lane at a time: the two give the same bits.
uint32_t triangles_apart4(const double* V, const int32_t* F, const FacePair* pairs);
// The same without AVX2 (for the tests: both paths must agree).
uint32_t triangles_apart4_portable(const double* V, const int32_t* F, const FacePair* pairs);
// Bit l set: pairs[l] collides, exactly as triangles_collide answers. The plane rejection above
// settles most pairs; of the others, the generic ones are decided in the same four lanes from
// the signs it proved (with two more filtered orient3d where no corner is shared), the rest by
// triangles_collide.
uint32_t triangles_collide4(const double* V, const int32_t* F, const FacePair* pairs);
// The same without AVX2: the plane rejection, then triangles_collide.
uint32_t triangles_collide4_portable(const double* V, const int32_t* F, const FacePair* pairs);
// triangles_collide on one pair of rows of F (positions V).
bool triangles_collide_rows(const double* V, const int32_t* F, const FacePair& pair);
// Whether triangles_apart4 runs its AVX2 path on this CPU.
bool triangles_apart4_vectorised();

}  // namespace conecull
