"""Ties between a 6-DOF reference node and the 3-DOF nodes of a solid face.

Both ties are linear constraint equations (slave DOF → {master DOF: coefficient}) for
:func:`rvcoax.fem.constraints.elimination_matrix`, so they assemble into the system like rigid links.

* **Rigid tie (RBE2-like)**: every face node follows the reference node as a rigid body,
  u_i = u_c + θ_c × (x_i − x_c). Slaves: the face DOFs. Use it where the real joint is stiff
  (a bolted flange).
* **Distributing tie (RBE3-like)**: the reference node moves with the weighted mean of the face,
  u_c = Σ w̄_i u_i + θ × (x_c − x̄) with θ = A⁻¹ Σ w_i r_i × u_i, r_i = x_i − x̄,
  A = Σ w_i (|r_i|² I − r_i r_iᵀ). Slaves: the reference node's six DOFs. A force or moment on the
  reference node is spread over the face in proportion to the weights (load averaging) without
  stiffening the face. Use it for bearings, mounts and coupling hubs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvcoax.fem import DOFS_PER_NODE

__all__ = ["FaceNodes", "distributing_tie_equations", "distributing_tie_operator", "face_nodes", "rigid_tie_equations"]


@dataclass(frozen=True)
class FaceNodes:
    """The nodes of a solid face.

    Parameters
    ----------
    coordinates : (n, 3) array
        Node positions (m).
    dofs : (n, 3) int array
        Global DOF numbers of ux, uy, uz of each node.
    weights : (n,) array
        Positive weights (e.g. the face area attributed to each node).
    """

    coordinates: np.ndarray
    dofs: np.ndarray
    weights: np.ndarray


def face_nodes(mesh, basis, facets: np.ndarray, offset: int = 0) -> FaceNodes:
    """The P2 nodes of a set of facets of a tetrahedral ``mesh`` (vector P2 ``basis``) with DOFs shifted by
    ``offset`` and area weights (area / 6 per facet node)."""
    corners = mesh.p[:, mesh.facets[:, facets]]
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0], axis=0), axis=0)
    vertex_ids = mesh.facets[:, facets]          # (3, n)
    edge_ids = mesh.f2e[:, facets]               # (3, n)
    vertex_dofs = basis.nodal_dofs[:, vertex_ids.ravel()].T       # (3n, 3)
    edge_dofs = basis.edge_dofs[:, edge_ids.ravel()].T
    dofs = np.vstack([vertex_dofs, edge_dofs])
    share = np.concatenate([np.tile(area / 6.0, 3), np.tile(area / 6.0, 3)])
    unique, inverse = np.unique(dofs[:, 0], return_inverse=True)
    weights = np.zeros(unique.size)
    np.add.at(weights, inverse, share)
    first = np.zeros(unique.size, dtype=int)
    first[inverse] = np.arange(dofs.shape[0])
    node_dofs = dofs[first]
    coordinates = basis.doflocs[:, node_dofs[:, 0]].T
    return FaceNodes(coordinates, node_dofs + offset, weights)


def _cross_matrix(r: np.ndarray) -> np.ndarray:
    """[r]× for each row of r, shape (n, 3, 3): [r]× v = r × v."""
    m = np.zeros((r.shape[0], 3, 3))
    m[:, 0, 1], m[:, 0, 2] = -r[:, 2], r[:, 1]
    m[:, 1, 0], m[:, 1, 2] = r[:, 2], -r[:, 0]
    m[:, 2, 0], m[:, 2, 1] = -r[:, 1], r[:, 0]
    return m


def rigid_tie_equations(reference_node: int, reference_point: np.ndarray, face: FaceNodes) -> dict[int, dict[int, float]]:
    """Face DOFs as slaves of the reference node: u_i = u_c + θ_c × (x_i − x_c)."""
    base = DOFS_PER_NODE * reference_node
    arms = face.coordinates - np.asarray(reference_point)
    equations: dict[int, dict[int, float]] = {}
    for r, dofs in zip(arms, face.dofs):
        # θ × r = (θy rz − θz ry, θz rx − θx rz, θx ry − θy rx)
        equations[int(dofs[0])] = {base + 0: 1.0, base + 4: r[2], base + 5: -r[1]}
        equations[int(dofs[1])] = {base + 1: 1.0, base + 5: r[0], base + 3: -r[2]}
        equations[int(dofs[2])] = {base + 2: 1.0, base + 3: r[1], base + 4: -r[0]}
    return equations


def distributing_tie_operator(reference_point: np.ndarray, face: FaceNodes) -> np.ndarray:
    """(6, 3n) operator giving the reference node's [u_c, θ_c] from the face displacements."""
    w = np.asarray(face.weights, dtype=float)
    if np.any(w <= 0.0) or w.size < 3:
        raise ValueError("a distributing tie needs at least three face nodes with positive weights")
    w_bar = w / w.sum()
    centroid = w_bar @ face.coordinates
    r = face.coordinates - centroid
    cross = _cross_matrix(r)  # [r_i]×
    a = np.einsum("i,ikj,ikl->jl", w, cross, cross)  # Σ w_i [r_i]×ᵀ [r_i]× = Σ w_i (|r|² I − r rᵀ)
    if np.linalg.cond(a) > 1e12:
        raise ValueError("the face nodes of a distributing tie are collinear: its rotation is undefined")
    a_inv = np.linalg.inv(a)
    n = w.size
    rotation = np.einsum("jk,i,ikl->jil", a_inv, w, cross).reshape(3, 3 * n)  # θ = A⁻¹ Σ w_i r_i × u_i
    translation = np.zeros((3, 3 * n))
    for k in range(3):
        translation[k, k::3] = w_bar
    # u_c = ū + θ × (x_c − x̄) = ū − [x_c − x̄]× θ
    offset = _cross_matrix((np.asarray(reference_point) - centroid)[None, :])[0]
    return np.vstack([translation - offset @ rotation, rotation])


def distributing_tie_equations(reference_node: int, reference_point: np.ndarray, face: FaceNodes,
                               drop_below: float = 1e-14) -> dict[int, dict[int, float]]:
    """The reference node's six DOFs as slaves of the face DOFs (RBE3-like)."""
    operator = distributing_tie_operator(reference_point, face)
    columns = np.asarray(face.dofs, dtype=int).reshape(-1)
    scale = np.abs(operator).max(axis=1, keepdims=True)
    keep = np.abs(operator) > drop_below * scale
    base = DOFS_PER_NODE * reference_node
    return {base + k: {int(c): float(v) for c, v, ok in zip(columns, operator[k], keep[k]) if ok} for k in range(6)}
