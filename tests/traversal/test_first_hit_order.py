"""first_hit_order (core/include/conecull/traversal/parallel_self_collide.hpp), the order in
which dcd(stop_at_first) visits its top tasks, against a Python model on random pre-order trees:
the lowest common ancestor found by walking parent links, distant-first = stable sort by its
depth, the two orders taking turns. Every task is visited once, and each within twice its place
in whichever order reaches it first. Bad trees and tasks raise ValueError naming the argument."""

import numpy as np
import pytest

from conecull import _core


def random_tree(rng, n_leaves):
    """(right, depth) of a random binary tree in pre-order, as bvh.cpp lays one out."""
    right, depth = [], []

    def emit(leaves, d):
        i = len(right)
        right.append(-1)
        depth.append(d)
        if leaves > 1:
            k = int(rng.integers(1, leaves))
            emit(k, d + 1)
            right[i] = len(right)
            emit(leaves - k, d + 1)

    emit(n_leaves, 0)
    return np.array(right, np.int32), np.array(depth, np.int32)


def model_order(right, depth, tasks):
    parent = np.full(len(right), -1)
    for i, r in enumerate(right):
        if r >= 0:
            parent[i + 1] = parent[r] = i

    def ancestors(x):
        out = [x]
        while parent[out[-1]] >= 0:
            out.append(parent[out[-1]])
        return out

    def lca_depth(a, b):
        if b < 0:
            return depth[a]
        up = set(ancestors(a))
        return depth[next(x for x in ancestors(b) if x in up)]

    n = len(tasks)
    distant = sorted(range(n), key=lambda k: lca_depth(*tasks[k]))  # stable: ties in task order
    taken, order, i, j = set(), [], 0, 0
    while len(order) < n:
        while i < n and i in taken:
            i += 1
        if i < n:
            taken.add(i)
            order.append(i)
        while j < n and distant[j] in taken:
            j += 1
        if j < n:
            taken.add(distant[j])
            order.append(distant[j])
    return order, distant


def subtree(right, x):
    """Pre-order range of x's subtree."""
    end, stack = x + 1, [x]
    while stack:
        y = stack.pop()
        end = max(end, y + 1)
        if right[y] >= 0:
            stack += [y + 1, right[y]]
    return range(x, end)


@pytest.mark.parametrize("seed", range(40))
def test_first_hit_order_matches_model(seed):
    rng = np.random.default_rng(seed)
    right, depth = random_tree(rng, int(rng.integers(1, 60)))
    n = len(right)
    tasks = []
    for _ in range(int(rng.integers(0, 300))):
        a = int(rng.integers(n))
        if rng.random() < 0.3:
            tasks.append((a, -1))  # a self task
            continue
        inside = set(subtree(right, a))
        b = int(rng.integers(n))
        if b in inside or a in subtree(right, b):
            continue  # a task pairs nodes with disjoint triangle sets
        tasks.append((a, b))
    got = _core.traversal.first_hit_order(right, depth, np.array(tasks, np.int32).reshape(-1, 2)).tolist()
    order, distant = model_order(right, depth, tasks)
    assert got == order
    assert sorted(got) == list(range(len(tasks)))
    place = {k: p for p, k in enumerate(got)}
    for k in range(len(tasks)):
        assert place[k] <= 2 * min(k, distant.index(k)) + 1


def test_first_hit_order_bad_input():
    right, depth = np.array([2, -1, -1], np.int32), np.array([0, 1, 1], np.int32)
    order = _core.traversal.first_hit_order
    assert order(right, depth, np.array([[1, 2], [0, -1]], np.int32)).tolist() == [0, 1]
    for bad_right, what in (([1, -1, -1], "right child 1"), ([2, -1], "depth"), ([2, 5, -1], "right child 5"),
                            ([-1, -1, -1], "not in the tree")):
        with pytest.raises(ValueError, match="right|depth") as e:
            order(np.array(bad_right, np.int32), depth, np.zeros((0, 2), np.int32))
        assert what in str(e.value), (bad_right, str(e.value))
    with pytest.raises(ValueError, match="depth: node 1 has depth 2"):
        order(right, np.array([0, 2, 1], np.int32), np.zeros((0, 2), np.int32))
    with pytest.raises(ValueError, match="tasks: row 0"):
        order(right, depth, np.array([[3, 1]], np.int32))
    with pytest.raises(ValueError, match="tasks: expected shape"):
        order(right, depth, np.array([1, 2], np.int32))
