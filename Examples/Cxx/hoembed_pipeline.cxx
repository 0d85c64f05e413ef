// The whole HOEmbed pipeline in C++: fine surface -> curved tet10 mesh -> embedding ->
// co-rotated simulation -> deformed fine surface -> .pvd time series.
//
//   hoembed_pipeline OUTPUT_FOLDER
#include "vtkCorotationalFEMStepper.h"
#include "vtkDeformationTransferFilter.h"
#include "vtkEmbeddingCoordinatesFilter.h"
#include "vtkTet10Mesher.h"
#include "vtkTimeSeriesWriter.h"

#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkUnstructuredGrid.h"

#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  const std::string out = argc > 1 ? argv[1] : "hoembed_example_output";

  // A fine surface (any vtkPolyData source or reader works here).
  vtkNew<vtkSphereSource> surface;
  surface->SetThetaResolution(200);
  surface->SetPhiResolution(200);

  // 1. Coarse, curved, valid tet10 mesh.
  vtkNew<vtkTet10Mesher> mesher;
  mesher->SetInputConnection(surface->GetOutputPort());
  mesher->SetTargetNumberOfElements(300);

  // 2. Embedding coordinates of the surface in the rest mesh.
  vtkNew<vtkEmbeddingCoordinatesFilter> embed;
  embed->SetInputConnection(0, surface->GetOutputPort());
  embed->SetInputConnection(1, mesher->GetOutputPort());

  // 3. Co-rotated tet10 elasticity under gravity, bottom clamped.
  vtkNew<vtkCorotationalFEMStepper> stepper;
  stepper->SetInputConnection(mesher->GetOutputPort());
  stepper->SetYoungModulus(2e4);
  stepper->SetPoissonRatio(0.49);
  stepper->SetDensity(1000);
  stepper->SetGravity(9.81, 0, 0);
  stepper->SetTimeStep(0.02);
  stepper->SetNumberOfTimeSteps(10);
  stepper->SetUseClampPlane(true);
  stepper->SetClampPlaneOrigin(0, 0, -0.35);
  stepper->SetClampPlaneNormal(0, 0, 1);

  // 4. The deformed fine surface for every frame.
  vtkNew<vtkDeformationTransferFilter> transfer;
  transfer->SetInputConnection(0, embed->GetOutputPort());
  transfer->SetInputConnection(1, stepper->GetOutputPort());

  // 5. Time series of both (ParaView / pyvista open the .pvd files).
  vtkNew<vtkTimeSeriesWriter> meshWriter;
  meshWriter->SetInputConnection(stepper->GetOutputPort());
  meshWriter->SetFileName((out + "/fe_mesh.pvd").c_str());
  vtkNew<vtkTimeSeriesWriter> surfaceWriter;
  surfaceWriter->SetInputConnection(transfer->GetOutputPort());
  surfaceWriter->SetFileName((out + "/surface.pvd").c_str());
  if (!meshWriter->Write() || !surfaceWriter->Write())
  {
    std::cerr << "hoembed_pipeline: writing the series failed\n";
    return 1;
  }
  std::cout << "mesh: " << mesher->GetOutput()->GetNumberOfCells() << " tet10 elements; wrote "
            << out << "/fe_mesh.pvd and " << out << "/surface.pvd\n";
  return 0;
}
