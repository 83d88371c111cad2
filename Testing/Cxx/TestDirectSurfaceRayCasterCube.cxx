int TestDirectSurfaceRayCasterCube(int, char*[]) { return 0; }
