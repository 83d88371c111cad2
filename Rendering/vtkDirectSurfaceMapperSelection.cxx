// vtkDirectSurfaceMapper's hardware selection (vtkHardwareSelector: ParaView's Select Cells /
// Points On, hovering, vtkPropPicker): one exact cast per selection, shared by its passes (the
// last full-resolution frame's when it shows the same view, or the view's background cast of it,
// waited for), and in each pass the ids it asks for drawn at every covered pixel with the
// surface's exact depth.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkCompositeDataSet.h"
#include "vtkHardwareSelector.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::DrawSelection(vtkRenderer* renderer, vtkActor* actor)
{
  vtkHardwareSelector* selector = renderer->GetSelector();
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow());
  if (!window || !actor)
  {
    return;
  }
  if (!this->Static)
  {
    this->Update();
  }
  Frame frame(window, actor, false);
  frame.Selecting = true;
  if (!this->CollectBlocks(frame) || !frame.SetUpView(renderer, 1.0))
  {
    return;
  }
  Internals& in = *this->Internal;
  Internals::ViewResources& gl = in.ResourcesOf(window, renderer, actor, frame.Eye);
  auto& image = gl.Selection;

  // The passes of one selection share one cast: of the view, the data and the settings that
  // decide what each pixel shows (not its colour).
  this->ComputeSignature(frame, false);
  std::vector<double> signature = frame.SelectionSignature();
  vtkIdType maximumPointId = 0, maximumCellId = 0;
  for (const auto& block : frame.Blocks)
  {
    maximumPointId = std::max(maximumPointId, block.second->GetNumberOfPoints() - 1);
    maximumCellId = std::max(maximumCellId, block.second->GetNumberOfCells() - 1);
  }
  if (signature == image.FailedSignature)
  {
    return; // (said at this selection's first pass; the other passes say nothing more)
  }
  // The exact image is needed now: the last full-resolution frame's (KeepForSelection), or this
  // view's background cast of the same view, waited for (it is no longer than a new cast).
  Refinement* refining = gl.Refining.get();
  if (signature != image.Signature && refining && refining->SelectionSignature == signature)
  {
    if (refining->Worker.joinable())
    {
      refining->Worker.join();
    }
    if (refining->Finished)
    {
      image.Keep(frame, refining->Cast, signature);
    }
  }
  if (signature != image.Signature)
  {
    image.Signature.clear();
    image.FailedSignature = signature;
    if (!this->ConvertSettings(frame))
    {
      return;
    }
    // (A cast of other data or settings may rebuild the prepared meshes they read.)
    in.CancelRefinements(&frame);
    if (!this->CastBlocks(frame))
    {
      return;
    }
    image.FailedSignature.clear();
    in.ComputeWindowDepth(frame);
    image.Keep(frame, in.Cast, std::move(signature));
  }

  const int pass = selector->GetCurrentPass();
  if (pass == vtkHardwareSelector::ACTOR_PASS)
  {
    // The id passes of more than 24 bits are asked for from these.
    selector->UpdateMaximumCellId(maximumCellId);
    selector->UpdateMaximumPointId(maximumPointId);
  }
  if ((pass == vtkHardwareSelector::POINT_ID_LOW24 ||
        pass == vtkHardwareSelector::POINT_ID_HIGH24) &&
    image.PointIds.empty())
  {
    image.FindNearestPoints(frame.Blocks);
  }
  selector->BeginRenderProp();
  image.EncodePass(pass, selector->GetPropColorValue(),
    vtkCompositeDataSet::SafeDownCast(frame.Input) != nullptr);
  Internals::LoadTextures(window, image.IdTexture, image.DepthTexture, image.Width, image.Height,
    image.Ids.data(), image.WindowDepth.data());
  Internals::DrawTextures(
    gl, window, false, frame.Viewport, image.IdTexture, image.DepthTexture, false);
  selector->EndRenderProp();
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::Internals::ViewResources::SelectionImage::Keep(
  const Frame& frame, const ImageCast& cast, std::vector<double> signature)
{
  this->Width = frame.CastWidth;
  this->Height = frame.CastHeight;
  this->Rays = frame.Rays;
  this->CellIds = cast.CellIds;
  this->Depth = cast.Depth;
  this->WindowDepth = cast.WindowDepth;
  if (frame.SeveralBlocks())
  {
    this->Blocks = cast.PixelBlocks;
  }
  else
  {
    this->Blocks.assign(frame.Pixels(), frame.Blocks.front().first);
  }
  this->PointIds.clear();
  this->Signature = std::move(signature);
}

void vtkDirectSurfaceMapper::Internals::ViewResources::KeepForSelection(
  const Frame& frame, const ImageCast& cast)
{
  if (frame.ServesSelection())
  {
    this->Selection.Keep(frame, cast, frame.SelectionSignature());
  }
}

void vtkDirectSurfaceMapper::Internals::ViewResources::SelectionImage::FindNearestPoints(
  const std::vector<std::pair<unsigned int, vtkUnstructuredGrid*>>& blocks)
{
  std::map<unsigned int, vtkUnstructuredGrid*> grids(blocks.begin(), blocks.end());
  this->PointIds.assign(this->CellIds.size(), -1);
  vtkNew<vtkIdList> nodes;
  for (int j = 0; j < this->Height; ++j)
  {
    for (int i = 0; i < this->Width; ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * this->Width + i;
      const auto grid = grids.find(this->Blocks[p]);
      if (this->WindowDepth[p] >= 1.0f || this->CellIds[p] < 0 || grid == grids.end() ||
        this->CellIds[p] >= grid->second->GetNumberOfCells())
      {
        continue;
      }
      const tetdsr::Ray ray = this->Rays.pixelRay(i, j);
      const glm::dvec3 hit = ray.origin + this->Depth[p] * ray.direction;
      grid->second->GetCellPoints(this->CellIds[p], nodes);
      double nearest = std::numeric_limits<double>::infinity();
      for (vtkIdType k = 0; k < nodes->GetNumberOfIds(); ++k)
      {
        double x[3];
        grid->second->GetPoint(nodes->GetId(k), x);
        const double d = glm::distance(glm::dvec3(x[0], x[1], x[2]), hit);
        if (d < nearest)
        {
          nearest = d;
          this->PointIds[p] = nodes->GetId(k);
        }
      }
    }
  }
}

void vtkDirectSurfaceMapper::Internals::ViewResources::SelectionImage::EncodePass(
  int pass, const float* propColor, bool composite)
{
  std::uint8_t propBytes[3];
  for (int c = 0; c < 3; ++c)
  {
    propBytes[c] = static_cast<std::uint8_t>(std::lround(255.0 * propColor[c]));
  }
  const std::size_t pixels = this->CellIds.size();
  this->Ids.assign(4 * pixels, 0);
  // The id passes: the cells' or the points' ids, their low or high 24 bits.
  const bool cellPass =
    pass == vtkHardwareSelector::CELL_ID_LOW24 || pass == vtkHardwareSelector::CELL_ID_HIGH24;
  const bool pointPass =
    pass == vtkHardwareSelector::POINT_ID_LOW24 || pass == vtkHardwareSelector::POINT_ID_HIGH24;
  const int shift =
    pass == vtkHardwareSelector::CELL_ID_HIGH24 || pass == vtkHardwareSelector::POINT_ID_HIGH24 ? 24 : 0;
  const std::vector<tetdsr::NodeId>* ids =
    cellPass ? &this->CellIds : (pointPass ? &this->PointIds : nullptr);
  for (std::size_t p = 0; p < pixels; ++p)
  {
    std::uint8_t* rgba = &this->Ids[4 * p];
    rgba[3] = 255;
    long long value = 0;
    if (ids)
    {
      value = ((*ids)[p] >> shift) & 0xffffff;
    }
    else if (pass == vtkHardwareSelector::COMPOSITE_INDEX_PASS)
    {
      // (vtkCompositePolyDataMapper2's flat index of a block; 1 for a dataset, as VTK's
      // polygon mappers write it.)
      value = composite ? this->Blocks[p] : 1;
    }
    else // the actor's and the process's passes: the selector's colour
    {
      std::copy_n(propBytes, 3, rgba);
      continue;
    }
    rgba[0] = static_cast<std::uint8_t>(value & 0xff);
    rgba[1] = static_cast<std::uint8_t>((value >> 8) & 0xff);
    rgba[2] = static_cast<std::uint8_t>((value >> 16) & 0xff);
  }
}
