// What the parts of tetdsr._core share (module.cpp: the mesh, images and checks;
// exact_surface.cpp: the exact surface as data): the arrays numpy hands over, the prepared mesh
// and its locks, the core's ParallelFor on std::threads, and each part's Bind function.
#pragma once

#include "tetdsr/index/Scene.h"
#include "tetdsr/index/SurfaceIndex.h"
#include "tetdsr/input/MeshInput.h"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

namespace nb = nanobind;

namespace tetdsr_python
{

template <typename T>
using Array = nb::ndarray<T, nb::c_contig, nb::device::cpu>;
/// An array of any number type (the core reads VTK's types).
using AnyArray = nb::ndarray<nb::c_contig, nb::device::cpu>;

/// The core's ParallelFor on `threads` threads, in chunks of a 256th of the indices but at least
/// `minimumChunk` (1024 for cheap steps such as validating a cell; 1 where one index can cost
/// milliseconds, as a cell the exact surface is refined in).
tetdsr::ParallelFor CellsFor(int threads, tetdsr::NodeId minimumChunk = 1024);

/// A ValueError carrying the core's first error (for arguments a face should have checked).
[[noreturn]] void ThrowFirstError(const tetdsr::Messages& messages);

/// The core's view of a numpy array: (tuples,) or (tuples, components), any number type.
tetdsr::ArrayView ViewOf(const AnyArray& array, const std::string& name, const char* what);

/// The core's PreparedMesh and copies of the arrays its scene views: the core trusts what it
/// validated (ids in range, finite coordinates and values), so an in-place numpy edit of the
/// caller's arrays afterwards (an id set to 10^12, a point to NaN) must not reach it: a kept
/// scene renders what was prepared until the next prepare. `Generation` counts prepares, so that
/// a Renderer of an earlier scene refuses to cast instead of reading freed memory.
///
/// Threads (Python threads run the calls below with the GIL released): `SceneLock` is held
/// exclusively by prepare and shared by everything that reads the scene (a cast holds it
/// throughout); `CacheLock` guards what is built on demand for a scene: the surface indices
/// (each Renderer shares the one it casts into, so building another never frees it), the nodal
/// gradients and the core's colour array cache. Locks are taken with the GIL released.
struct PyPreparedMesh
{
  tetdsr::PreparedMesh Core;
  std::vector<std::vector<unsigned char>> Copied;
  std::uint64_t Generation = 0;
  std::shared_ptr<const tetdsr::SurfaceIndex> Surface; // of the last iso-values asked for
  std::vector<double> SurfaceValues;
  mutable std::shared_mutex SceneLock;
  std::mutex CacheLock;

  tetdsr::Scene& SceneOrThrow() const
  {
    tetdsr::Scene* scene = this->Core.scene();
    if (!scene)
    {
      throw nb::value_error("the PreparedMesh has no scene: its last prepare failed");
    }
    return *scene;
  }
};

/// A lock of `mutex` taken with the GIL released (a thread holding the lock may wait for the
/// GIL: a cast's abort and progress callbacks).
template <typename Lock, typename Mutex>
Lock LockWithoutGil(Mutex& mutex)
{
  nb::gil_scoped_release release;
  return Lock(mutex);
}

using SharedLock = std::shared_lock<std::shared_mutex>;
using ExclusiveLock = std::unique_lock<std::shared_mutex>;

/// The exact surface as data (exact_surface.cpp).
void BindExactSurface(nb::module_& m);

} // namespace tetdsr_python
