/**
 * @class   vtkTimeSeriesWriter
 * @brief   writes a time series: one VTK XML file per step plus a ParaView .pvd collection
 *
 * FileName is the path of the collection, e.g. `out/beam.pvd`; the step files go to the
 * folder next to it named after it (`out/beam/beam_000000.vtu`, ...) and the .pvd refers
 * to them by relative path, so the series can be moved as a whole. A vtkUnstructuredGrid
 * step is written as `.vtu` (vtkXMLUnstructuredGridWriter), a vtkPolyData step as `.vtp`
 * (vtkXMLPolyDataWriter); other data types are refused.
 *
 * Two ways to use it:
 * - Pipeline: connect the input and call Write(). The writer asks the input for its
 *   TIME_STEPS (or uses TimeValues when given) and updates it once per time, in order
 *   (UPDATE_TIME_STEP), writing each result; an input without time steps gives a
 *   one-step series at time 0.
 * - Frames: BeginSeries(), AddFrame(data, time) for each frame, EndSeries().
 *
 * No half-written series: every step file is written under a temporary name
 * (`.part`) and renamed when complete, and the .pvd is written last (also through a
 * temporary name). If anything fails, the files of the series written so far are
 * removed and no .pvd is created (an older series of the same name is left as it was).
 *
 * Defaults: FileName nullptr (required), TimeValues nullptr (use the input's).
 * Errors: vtkErrorMacro and a 0 return value.
 *
 * @sa vtkXMLUnstructuredGridWriter vtkXMLPolyDataWriter vtkCorotationalFEMStepper
 */
#ifndef vtkTimeSeriesWriter_h
#define vtkTimeSeriesWriter_h

#include "hoembedIOSeriesModule.h"
#include "vtkAlgorithm.h"

class vtkDataObject;
class vtkDoubleArray;

class HOEMBEDIOSERIES_EXPORT vtkTimeSeriesWriter : public vtkAlgorithm
{
public:
  static vtkTimeSeriesWriter* New();
  vtkTypeMacro(vtkTimeSeriesWriter, vtkAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Path of the .pvd collection file (the step files go in a folder beside it).
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Explicit list of times to write (nullptr: the input's TIME_STEPS).
  virtual void SetTimeValues(vtkDoubleArray*);
  vtkGetObjectMacro(TimeValues, vtkDoubleArray);
  ///@}

  /// Update the input over its time steps and write the series. Returns 1 on success.
  int Write();

  ///@{
  /// Frame-by-frame writing. Each returns 1 on success; a failed AddFrame abandons the
  /// series (its files are removed).
  int BeginSeries();
  int AddFrame(vtkDataObject* data, double time);
  int EndSeries();
  ///@}

  /// Number of step files in the last (or current) series.
  int GetNumberOfWrittenFrames();
  /// Path of the i-th step file of the last (or current) series ("" if out of range).
  const char* GetFrameFileName(int i);

protected:
  vtkTimeSeriesWriter();
  ~vtkTimeSeriesWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int, vtkInformation*) override { return 1; }

  char* FileName = nullptr;
  vtkDoubleArray* TimeValues = nullptr;

private:
  vtkTimeSeriesWriter(const vtkTimeSeriesWriter&) = delete;
  void operator=(const vtkTimeSeriesWriter&) = delete;

  void Abandon();
  struct Internals;
  Internals* Internal;
};

#endif
