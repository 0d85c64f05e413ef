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
 * No half-written series: the step files of a new series are written into a staging
 * folder beside the final one (`out/.beam.staging`), and the .pvd through a temporary
 * name (`out/beam.pvd.part`). Only when every frame and the collection are complete does
 * EndSeries swap them in: the old step folder is moved aside, the staging folder takes
 * its name, the .pvd is renamed over the old one (an atomic replace) and the old folder
 * is removed. So a run that fails (or a writer destroyed before EndSeries) leaves an
 * older series of the same name exactly as it was and removes what it wrote, and a
 * shorter re-run leaves no stale frames of the longer one.
 *
 * Refused up front (BeginSeries, nothing written): a .pvd path that is a folder, a step
 * folder path that is a file, and a step folder holding files that are not step files of
 * this series (`beam_NNNNNN.vtu/.vtp`): the writer replaces that folder as a whole and
 * will not delete someone else's files. AddFrame refuses a NaN or infinite time.
 *
 * The files of the series (staging, refusals, the .pvd text, the swap-in) are
 * hoembed::SeriesFiles' work (VTK-free, shared with the pip wheel); this class writes
 * each frame with the XML writers (appended data, zlib) into the path it gives.
 *
 * Defaults: FileName nullptr (required), TimeValues nullptr (use the input's).
 * Errors: vtkErrorMacro and a 0 return value.
 *
 * @sa hoembed::SeriesFiles vtkXMLUnstructuredGridWriter vtkXMLPolyDataWriter
 * vtkCorotationalFEMStepper
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
  /// Final path of the i-th step file of the last (or current) series ("" if out of
  /// range). While a series is open its files are still in the staging folder.
  const char* GetFrameFileName(int i);

protected:
  vtkTimeSeriesWriter();
  ~vtkTimeSeriesWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int, vtkInformation*) override
  {
    return 1;
  }

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
