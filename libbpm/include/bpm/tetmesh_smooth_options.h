#pragma once
// The options of smooth_tetmesh (bpm/tetmesh_smooth.h), in a header of their own so that
// bpm/tetmesh.h can hold them in TetMeshOptions without including the smoother (which
// works on a TetMesh and so includes bpm/tetmesh.h).

namespace bpm {

struct TetSmoothOptions {
    int sweeps = 3;                // passes over the vertices to improve (0 = nothing moves)
    double target_degrees = 15;    // a vertex is improved while a tetrahedron around it has a smaller dihedral angle
    bool laplacian = true;         // step 1 (smart Laplacian)
    bool optimize = true;          // step 2 (local optimisation of the worst dihedral angle)
    int max_iterations = 3;        // optimisation steps per vertex and visit (more sweeps beat more steps)
};

}  // namespace bpm
