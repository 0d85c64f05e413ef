#include "vtkTet10Mesher.h"

#include "vtkInformation.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkTet10Mesher);

vtkTet10Mesher::vtkTet10Mesher() = default;
vtkTet10Mesher::~vtkTet10Mesher() = default;

int vtkTet10Mesher::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkTet10Mesher::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*)
{
  vtkErrorMacro("work in progress");
  return 0;
}

void vtkTet10Mesher::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
