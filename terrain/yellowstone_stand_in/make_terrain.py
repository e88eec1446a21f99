#!/usr/bin/env python3
"""Writes yellowstone_stand_in_25m.tif: a straight stand-in for the Yellowstone River valley
below Laurel, Montana (the 2011 Silvertip pipeline spill, configs/far_field/yellowstone_2011.json).

No elevation model of the reach ships with the project, so this is not the river's terrain: a
straight valley running east from the spill site, on 25 m cells in UTM zone 12N (EPSG:32612),
with a compound section made of the few facts that are public (see terrain/README.md):
  - main channel: 120 m flat bottom, 3 m below the floodplain's edge, banks 1 in 3;
  - floodplain: 230 m each side, rising 1 m away from the river (the flood of July 2011 was
    over its banks: the EPA reported oil "along the banks and overland");
  - valley walls beyond 300 m from the centre, rising 10 m over 50 m;
  - bed slope 0.0015 down the valley (about the Yellowstone's fall between Laurel and Billings).
Usage: python3 make_terrain.py  (needs GDAL's Python bindings; writes next to itself)
"""
import os

import numpy as np
from osgeo import gdal, osr

CELL = 25.0
SPILL_E, SPILL_N = 673580.0, 5059700.0  # EPA's site position (45.66912 N, 108.77153 W) in UTM 12N
UPSTREAM = 2000.0                        # m of valley above the spill
DOWNSTREAM = 110000.0                    # m below it
HALF_WIDTH = 375.0                       # m either side of the centreline
SLOPE = 0.0015
Z_SPILL = 985.0                          # m: the floodplain's edge at the spill (about Laurel's)


def section(d):
    """Height above the floodplain's edge at distance d (m) from the centreline."""
    d = np.abs(d)
    z = np.where(d <= 60, -3.0, -3.0 + (d - 60) / 3.0)
    z = np.where(d > 69, (d - 69) / 231.0, z)
    z = np.where(d > 300, 1.0 + 10.0 * np.minimum(d - 300, 50) / 50.0, z)
    return z


def main():
    nx = int(round((UPSTREAM + DOWNSTREAM) / CELL))
    ny = int(round(2 * HALF_WIDTH / CELL))
    x0, y_top = SPILL_E - UPSTREAM, SPILL_N + HALF_WIDTH
    xc = x0 + (np.arange(nx) + 0.5) * CELL
    yc = y_top - (np.arange(ny) + 0.5) * CELL
    X, Y = np.meshgrid(xc, yc)
    z = Z_SPILL - SLOPE * (X - SPILL_E) + section(Y - SPILL_N)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "yellowstone_stand_in_25m.tif")
    ds = gdal.GetDriverByName("GTiff").Create(
        path, nx, ny, 1, gdal.GDT_Float32, ["COMPRESS=DEFLATE", "PREDICTOR=3", "TILED=YES"])
    ds.SetGeoTransform((x0, CELL, 0, y_top, 0, -CELL))
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(32612)
    ds.SetProjection(srs.ExportToWkt())
    ds.GetRasterBand(1).WriteArray(z.astype(np.float32))
    ds = None
    print(f"{path}: {nx} x {ny} cells of {CELL} m, x {x0:.0f}..{x0 + nx * CELL:.0f}, "
          f"y {y_top - ny * CELL:.0f}..{y_top:.0f}, z {z.min():.1f}..{z.max():.1f} m")


if __name__ == "__main__":
    main()
