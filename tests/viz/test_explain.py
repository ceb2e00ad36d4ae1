"""explain_node refuses what it cannot explain, naming the argument: a result of another
collider, an untraced result, a bad node id, a collider without a BVH yet."""

import dataclasses

import pytest

import conecull
from conecull.datasets.generated import folding_sheet
from conecull.viz.explain import explain_node


def traced(n_triangles, method="nc"):
    F, P = folding_sheet(n_triangles, 4)
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    col.dcd(P[0])
    return col, col.dcd(P[-1], trace=True), P


@pytest.fixture(scope="module")
def sheets():
    return traced(200), traced(2000), traced(160), traced(200, method="aabb")


def test_explains_its_own_result(sheets):
    col, res, _ = sheets[0]
    assert explain_node(col, res, 0).startswith("node 0: depth 0")


@pytest.mark.parametrize("other", [1, 2])
def test_refuses_a_result_of_another_mesh(sheets, other):
    col, res, _ = sheets[0]
    col2, res2, _ = sheets[other]
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(col, res2, 0)
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(col2, res, 0)
    with pytest.raises(ValueError, match="res: comes from another collider"):  # judged by its trace
        explain_node(col, dataclasses.replace(res2, collider=None), 0)


def test_refuses_a_result_of_another_method(sheets):
    col, res, _ = sheets[0]
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(col, sheets[3][1], 0)
    # a result without its collider (built by hand) is judged by what its trace shows
    with pytest.raises(ValueError, match="res: comes from a query with method 'aabb', but col uses 'nc'"):
        explain_node(col, dataclasses.replace(sheets[3][1], collider=None), 0)


def test_refuses_a_result_of_a_twin_collider(sheets):
    """Same mesh, same method, same poses: the trace cannot tell the two apart, the result can."""
    col, res, P = sheets[0]
    twin = conecull.SelfCollider(col.mesh, method=col.method)
    twin.dcd(P[0])
    assert res.collider() is col
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(twin, res, 0)
    assert explain_node(twin, dataclasses.replace(res, collider=None), 0) == explain_node(col, res, 0)


def test_refuses_an_untraced_result(sheets):
    col, _, P = sheets[0]
    with pytest.raises(ValueError, match=r"res: the query was not traced; run it with trace=True"):
        explain_node(col, col.dcd(P[-1]), 0)


@pytest.mark.parametrize("node,match", [
    (1.5, r"node: expected an integer node id in 0\.\.198, got 1\.5"),
    ("3", r"node: expected an integer node id in 0\.\.198, got '3'"),
    (199, r"^node: 199 is out of range: the BVH has nodes 0\.\.198"),
    (-1, r"^node: -1 is out of range"),
])
def test_names_a_bad_node(sheets, node, match):
    col, res, _ = sheets[0]
    with pytest.raises(ValueError, match=match):  # `node`, the Python name: the CLI says --node
        explain_node(col, res, node)


def test_before_any_query(sheets):
    col, res, _ = sheets[0]
    fresh = conecull.SelfCollider(col.mesh)
    with pytest.raises(ValueError, match=r"col: has no BVH yet .*run col\.dcd\(V\) first"):
        explain_node(fresh, res, 0)
