// Test helper for vtkEmbeddingCoordinatesFilter: run it and keep its output.
#ifndef hoembedEmbeddingTestUtilities_h
#define hoembedEmbeddingTestUtilities_h

#include "hoembedTestUtilities.h"
#include "vtkEmbeddingCoordinatesFilter.h"

#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

/// The filter's output for `surface` on `mesh` (Method `method`); `errorObserver`, when
/// given, watches the filter's and its executive's error events. Checks that the
/// certified face search finished within its budget everywhere (else the filter warns
/// and the distances may be local minima).
inline vtkSmartPointer<vtkPolyData> RunEmbeddingFilter(vtkPolyData* surface,
  vtkUnstructuredGrid* mesh, int method = 0, vtkCommand* errorObserver = nullptr)
{
  vtkNew<vtkEmbeddingCoordinatesFilter> f;
  f->SetInputData(0, surface);
  f->SetMeshData(mesh);
  f->SetMethod(method);
  if (errorObserver)
  {
    f->AddObserver(vtkCommand::ErrorEvent, errorObserver);
    f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errorObserver);
  }
  f->Update();
  HOEMBED_CHECK(f->GetNumberOfUncertifiedPoints() == 0, "%lld points left uncertified",
    static_cast<long long>(f->GetNumberOfUncertifiedPoints()));
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

#endif
