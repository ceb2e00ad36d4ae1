// Traversal bindings (core/include/conecull/traversal/): the first-hit order of the top tasks.
#include <string>

#include "conecull/traversal/parallel_self_collide.hpp"
#include "stages.hpp"

namespace conecull::bind {

namespace {

// A BVH shape from (right, depth) per node in pre-order, checked to be one: node i's left child
// is i + 1, its right child right[i] (-1 for a leaf), and children are one level deeper.
Bvh bvh_shape(const I32Array& right, const I32Array& depth) {
    if (right.ndim() != 1) throw py::value_error("right: expected shape (n,), got " + shape_str(right));
    const auto n = static_cast<int32_t>(right.shape(0));
    if (depth.ndim() != 1 || depth.shape(0) != n)
        throw py::value_error("depth: expected shape (" + std::to_string(n) + ",), got " + shape_str(depth));
    Bvh bvh;
    bvh.nodes.resize(n);
    // Walk the pre-order: every node must be the next one expected, with its depth.
    std::vector<std::pair<int32_t, int32_t>> stack;  // (node expected next, its depth)
    if (n > 0) stack.push_back({0, 0});
    int32_t next = 0;
    while (!stack.empty()) {
        const auto [i, d] = stack.back();
        stack.pop_back();
        if (i != next || i >= n)
            throw py::value_error("right: not a pre-order binary tree (node " + std::to_string(i) + " out of place)");
        if (depth.data()[i] != d)
            throw py::value_error("depth: node " + std::to_string(i) + " has depth " + std::to_string(depth.data()[i]) +
                                  ", expected " + std::to_string(d));
        const int32_t r = right.data()[i];
        bvh.nodes[i].right = r;
        bvh.nodes[i].depth = d;
        ++next;
        if (r == -1) continue;
        if (r <= i + 1 || r >= n)
            throw py::value_error("right: node " + std::to_string(i) + " has right child " + std::to_string(r) +
                                  ", expected one in (" + std::to_string(i + 1) + ", " + std::to_string(n) + ") or -1");
        stack.push_back({r, d + 1});
        stack.push_back({i + 1, d + 1});
    }
    if (next != n) throw py::value_error("right: nodes " + std::to_string(next) + ".. are not in the tree of node 0");
    return bvh;
}

}  // namespace

void bind_traversal(py::module_& m) {
    m.def(
        "first_hit_order",
        [](const I32Array& right, const I32Array& depth, const I32Array& tasks) {
            const Bvh bvh = bvh_shape(right, depth);
            require_shape(tasks, "tasks", -1, 2);
            std::vector<BvttTask> ts(tasks.shape(0));
            for (py::ssize_t k = 0; k < tasks.shape(0); ++k) {
                const int32_t a = tasks.data()[2 * k], b = tasks.data()[2 * k + 1];
                if (a < 0 || a >= bvh.size() || b < -1 || b >= bvh.size())
                    throw py::value_error("tasks: row " + std::to_string(k) + " names a node outside [0, " +
                                          std::to_string(bvh.size()) + ") (b may be -1: a self task)");
                ts[k] = {a, b < 0 ? BvttTask::kSelfTask : b};
            }
            std::vector<int32_t> order;
            first_hit_order(bvh, ts, order);
            return to_numpy(order);
        },
        py::arg("right"), py::arg("depth"), py::arg("tasks"),
        "The order in which dcd(stop_at_first) visits its top tasks: traversal order and distant-first\n"
        "(by the depth of the lowest node holding both of a task's nodes) taking turns. right, depth:\n"
        "per node of a pre-order BVH (right child or -1, depth); tasks (k, 2): (a, b), b = -1 for a self\n"
        "task. Returns the task indices in visiting order.");
}

}  // namespace conecull::bind
