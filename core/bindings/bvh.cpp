// BVH bindings (core/include/conecull/bvh/bvh.hpp): the tree as NumPy arrays.
#include "stages.hpp"

namespace conecull::bind {

py::dict bvh_arrays(const Bvh& bvh) {
    const py::ssize_t n = bvh.size();
    py::array_t<double> box({n, py::ssize_t(2), py::ssize_t(3)});
    py::array_t<int32_t> left(n), right(n), begin(n), end(n), depth(n);
    auto b = box.mutable_unchecked<3>();
    for (py::ssize_t i = 0; i < n; ++i) {
        const BvhNode& node = bvh.nodes[i];
        for (int k = 0; k < 3; ++k) {
            b(i, 0, k) = node.box.lo[k];
            b(i, 1, k) = node.box.hi[k];
        }
        left.mutable_data()[i] = node.is_leaf() ? -1 : Bvh::left(static_cast<int32_t>(i));
        right.mutable_data()[i] = node.right;
        begin.mutable_data()[i] = node.begin;
        end.mutable_data()[i] = node.end;
        depth.mutable_data()[i] = node.depth;
    }
    py::dict d;
    d["box"] = box;
    d["left"] = left;
    d["right"] = right;
    d["begin"] = begin;
    d["end"] = end;
    d["depth"] = depth;
    d["order"] = to_numpy(bvh.order);
    d["leaf_size"] = bvh.leaf_size;
    return d;
}

void bind_bvh(py::module_&) {}

}  // namespace conecull::bind
