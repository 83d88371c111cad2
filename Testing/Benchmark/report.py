"""Joins tetdsr-benchmark's rows with vtk_wheel_contour.py's (and, where given, the Embree
comparison's one-thread rows) and prints the table (Markdown).

  report.py <tetdsr.tsv> <wheel.tsv> [embree.tsv]
Ratios are ours / theirs: below 1 means TetDSR is faster.
"""
import csv
import sys

ours = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
wheel = {(r["n"], r["field"]): r for r in csv.DictReader(open(sys.argv[2]), delimiter="\t")}
embree = {}
if len(sys.argv) > 3:
    embree = {(r["n"], r["field"]): r for r in csv.DictReader(open(sys.argv[3]), delimiter="\t")}
version = next(iter(wheel.values()))["vtk_version"] if wheel else "?"

print(f"| cells | field | TetDSR preprocess s | first frame s | after camera move s | M rays/s (all cores) "
      f"| M rays/s per core | after iso change s "
      f"| peak extra MB (mesh MB) | VTK 9.2 contour + render s (triangles) "
      f"| VTK {version} contour + render s | first frame / 9.2 | first frame / {version} "
      f"| iso change / 9.2 | iso change / {version} "
      f"| one core, same cells: our hierarchy / Embree BVH M rays/s (Embree packets) "
      f"| paper's 25% heuristic: cells missed, pixels lost |")
print("|" + "---|" * 17)
for r in ours:
    w = wheel.get((r["n"], r["field"]))
    e = embree.get((r["n"], r["field"]))
    theirs92 = float(r["contour_s"]) + float(r["render_s"])
    first, iso = float(r["first_s"]), float(r["iso_s"])
    if w:
        theirs_new = float(w["contour_s"]) + float(w["render_s"])
        new_cells = (f"{float(w['contour_s']):.3f} + {float(w['render_s']):.3f} = {theirs_new:.3f}",
                     f"{first / theirs_new:.2f}", f"{iso / theirs_new:.2f}")
    else:
        new_cells = ("-", "-", "-")
    embree_cell = (f"{float(e['ours_Mrays_core']):.2f} / {float(e['embree_Mrays_core']):.2f} "
                   f"({float(e['embree_packets_Mrays_core']):.2f})") if e else "-"
    rays = float(r["Mrays_s"])
    print(f"| {int(r['cells']):,} | {r['field']} | {float(r['pre_s']):.3f} | {first:.3f} "
          f"| {float(r['camera_s']):.3f} | {rays:.2f} | {rays / int(r['threads']):.2f} | {iso:.3f} "
          f"| {float(r['extra_MB']):.0f} ({float(r['mesh_MB']):.0f}) "
          f"| {float(r['contour_s']):.3f} + {float(r['render_s']):.3f} = {theirs92:.3f} ({int(r['triangles']):,}) "
          f"| {new_cells[0]} | {first / theirs92:.2f} | {new_cells[1]} | {iso / theirs92:.2f} | {new_cells[2]} "
          f"| {embree_cell} "
          f"| {int(r['heuristic_missed_cells']):,}, {int(r['heuristic_hole_pixels']):,} of {int(r['covered']):,} |")
