// Reads a Gmsh MSH 2.2 file with DUNE's own reader (Dune::GmshReader into a
// Dune::UGGrid<3>) and prints what a DUNE solver gets from it, as JSON on standard output:
//   {"elements": N, "element_ids": {"ID": count, ...}, "boundary_faces": M,
//    "boundary_ids": {"ID": count, ...}}
// element ids are the physical tags of the tetrahedra (bpm: material ids), boundary ids
// those of the boundary triangles (bpm: patch + 1). examples/dune/test_gmsh22.sh checks
// them against the file bpm-mesh --output-format msh22 wrote. Exit 1 if DUNE throws.
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <dune/common/exceptions.hh>
#include <dune/common/parallel/mpihelper.hh>
#include <dune/grid/io/file/gmshreader.hh>
#include <dune/grid/uggrid.hh>

namespace {

void print_counts(const char* name, const std::map<int, long>& counts) {
    std::cout << "\"" << name << "\": {";
    const char* separator = "";
    for (const auto& [id, count] : counts) {
        std::cout << separator << "\"" << id << "\": " << count;
        separator = ", ";
    }
    std::cout << "}";
}

}  // namespace

int main(int argc, char** argv) {
    Dune::MPIHelper::instance(argc, argv);
    if (argc != 2) {
        std::cerr << "usage: read_gmsh22 FILE.msh\n";
        return 2;
    }
    try {
        using Grid = Dune::UGGrid<3>;
        Dune::GridFactory<Grid> factory;
        std::vector<int> boundary_ids, element_ids;
        Dune::GmshReader<Grid>::read(factory, argv[1], boundary_ids, element_ids, /*verbose=*/false,
                                     /*insertBoundarySegments=*/true);
        const std::unique_ptr<Grid> grid = factory.createGrid();
        std::map<int, long> per_element_id, per_boundary_id;
        long elements = 0, boundary_faces = 0;
        for (const auto& element : Dune::elements(grid->leafGridView())) {
            ++elements;
            ++per_element_id[element_ids.at(factory.insertionIndex(element))];
            for (const auto& intersection : Dune::intersections(grid->leafGridView(), element)) {
                if (!intersection.boundary()) continue;
                ++boundary_faces;
                ++per_boundary_id[boundary_ids.at(factory.insertionIndex(intersection))];
            }
        }
        std::cout << "{\"elements\": " << elements << ", ";
        print_counts("element_ids", per_element_id);
        std::cout << ", \"boundary_faces\": " << boundary_faces << ", ";
        print_counts("boundary_ids", per_boundary_id);
        std::cout << "}\n";
    } catch (const Dune::Exception& e) {
        std::cerr << "read_gmsh22: DUNE: " << e.what() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "read_gmsh22: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
