// Where the points of a quad lie (plane or planet face), and the mesh of one elevation tile:
// its inner grid x grid cells, skirts hiding the cracks between levels, and the colours (a
// hillshade, or the ortho tile draped as a texture and shaded by the same light).
'use strict';

var PyramidMesh = (function () {
  // The terrain frame: x east (u right), y north (v up), z up (out of the planet). viewer.js
  // turns it into three.js's y-up world.

  // Plane: the root quad is sizeX x sizeY metres centred on the origin; heights in metres.
  function PlaneMapping(sizeX, sizeY, exaggeration) {
    this.sizeX = sizeX;
    this.sizeY = sizeY;
    this.exaggeration = exaggeration;
    this.rootSize = Math.max(sizeX, sizeY);
  }
  // (fx, fy): fractions of the root quad from its south-west corner; h: height in metres.
  PlaneMapping.prototype.point = function (fx, fy, h, out) {
    out[0] = (fx - 0.5) * this.sizeX;
    out[1] = (fy - 0.5) * this.sizeY;
    out[2] = h * this.exaggeration;
    return out;
  };
  PlaneMapping.prototype.cellSizes = function (level, grid) {
    var n = grid * Math.pow(2, level);
    return [this.sizeX / n, this.sizeY / n];
  };

  // Planet face: (u, v) = 2 (fx, fy) - 1 in [-1, 1]; the point at height h is
  // (radius + h) * normalize(frame * (u, v, 1)), frame given row by row ([[r0], [r1], [r2]]).
  function FaceMapping(radius, frame, exaggeration) {
    this.radius = radius;
    this.frame = frame;
    this.exaggeration = exaggeration;
    this.rootSize = 2 * radius; // the face of the cube, as the seeds' spherical terrains
  }
  FaceMapping.prototype.point = function (fx, fy, h, out) {
    var u = 2 * fx - 1, v = 2 * fy - 1, m = this.frame;
    var x = m[0][0] * u + m[0][1] * v + m[0][2];
    var y = m[1][0] * u + m[1][1] * v + m[1][2];
    var z = m[2][0] * u + m[2][1] * v + m[2][2];
    var r = (this.radius + h * this.exaggeration) / Math.sqrt(x * x + y * y + z * z);
    out[0] = x * r;
    out[1] = y * r;
    out[2] = z * r;
    return out;
  };
  FaceMapping.prototype.cellSizes = function (level, grid) {
    var c = this.rootSize / (grid * Math.pow(2, level));
    return [c, c];
  };

  // The light of the hillshade, in a tile's own frame (east or u, north or v, up): from the
  // azimuth (degrees clockwise from north) at the elevation (degrees above the horizon).
  function lightDirection(azimuthDeg, elevationDeg) {
    var az = azimuthDeg * Math.PI / 180, el = elevationDeg * Math.PI / 180;
    return [Math.cos(el) * Math.sin(az), Math.cos(el) * Math.cos(az), Math.sin(el)];
  }

  // The heights of a quad's vertices, (k, l) from its south-west corner in -1..grid + 1 (the
  // ring outside for normals): the elevation tile's own samples, or for a quad deeper than the
  // elevation pyramid (drawn for a finer ortho), the bilinear interpolation of its ancestor's
  // tile, `depth` levels up, the quad at (ox, oy) there (fractions of the ancestor).
  function heightLookup(tile) {
    var z = tile.heights, side = tile.side, b = tile.border, grid = tile.grid;
    var at = function (i, j) { return z[PyramidTiles.sampleIndex(side, i, j)]; };
    if (!tile.depth) return function (k, l) { return at(b + k, b + l); };
    var s = 1 / Math.pow(2, tile.depth);
    return function (k, l) {
      var x = b + (tile.ox + s * k / grid) * grid, y = b + (tile.oy + s * l / grid) * grid;
      var i = Math.min(Math.floor(x), side - 2), j = Math.min(Math.floor(y), side - 2);
      var fx = x - i, fy = y - j;
      return (at(i, j) * (1 - fx) + at(i + 1, j) * fx) * (1 - fy) +
        (at(i, j + 1) * (1 - fx) + at(i + 1, j + 1) * fx) * fy;
    };
  }

  // tile: {level, tx, ty, heights, side, border, grid, and for a quad deeper than its elevation
  // tile: depth, ox, oy (see heightLookup)}; ortho: null or {texture, side, border,
  // tileSize, ox, oy, scale} where (ox, oy) is the quad's south-west corner inside the ortho tile
  // and scale its size there (fractions of the ortho tile: 1 for a tile of the same level).
  // Returns {mesh, hmin, hmax}.
  function build(mapping, tile, ortho, light) {
    var grid = tile.grid;
    var vertsPerRow = grid + 1;
    var inner = vertsPerRow * vertsPerRow;
    var total = inner + 4 * vertsPerRow;
    var positions = new Float32Array(3 * total);
    var colours = new Float32Array(3 * total);
    var uvs = ortho ? new Float32Array(2 * total) : null;
    var span = 1 / Math.pow(2, tile.level);
    var x0 = tile.tx * span, y0 = tile.ty * span;
    var cells = mapping.cellSizes(tile.level, grid);
    var e = mapping.exaggeration;
    var p = [0, 0, 0];
    var origin = mapping.point(x0 + span / 2, y0 + span / 2, 0, [0, 0, 0]);
    var height = heightLookup(tile);

    var hmin = Infinity, hmax = -Infinity;
    for (var l = 0; l <= grid; ++l) {
      for (var k = 0; k <= grid; ++k) {
        var h = height(k, l);
        if (h < hmin) hmin = h;
        if (h > hmax) hmax = h;
      }
    }
    var skirt = Math.max((hmax - hmin) * 0.1, 2 * Math.min(cells[0], cells[1]) / Math.max(e, 1e-9));

    var put = function (index, k, l, drop) {
      var h = height(k, l);
      mapping.point(x0 + span * k / grid, y0 + span * l / grid, h - drop, p);
      positions[3 * index] = p[0] - origin[0];
      positions[3 * index + 1] = p[1] - origin[1];
      positions[3 * index + 2] = p[2] - origin[2];
      // The normal from the neighbouring samples (border samples at the tile's edges).
      var dzdx = (height(k + 1, l) - height(k - 1, l)) * e / (2 * cells[0]);
      var dzdy = (height(k, l + 1) - height(k, l - 1)) * e / (2 * cells[1]);
      var norm = Math.sqrt(dzdx * dzdx + dzdy * dzdy + 1);
      var shade = Math.max(0, (-dzdx * light[0] - dzdy * light[1] + light[2]) / norm);
      var c = ortho ? 0.5 + 0.5 * Math.min(1, shade / Math.max(light[2], 1e-3))
        : 0.06 + 0.94 * shade;
      colours[3 * index] = c;
      colours[3 * index + 1] = c;
      colours[3 * index + 2] = ortho ? c : c * 0.96;
      if (ortho) {
        var s = ortho.scale / grid;
        uvs[2 * index] = (ortho.border + (ortho.ox + s * k) * ortho.tileSize) / ortho.side;
        uvs[2 * index + 1] = (ortho.border + (ortho.oy + s * l) * ortho.tileSize) / ortho.side;
      }
    };

    var indices = [];
    for (var l2 = 0; l2 <= grid; ++l2) {
      for (var k2 = 0; k2 <= grid; ++k2) put(l2 * vertsPerRow + k2, k2, l2, 0);
    }
    for (var l3 = 0; l3 < grid; ++l3) {
      for (var k3 = 0; k3 < grid; ++k3) {
        var a = l3 * vertsPerRow + k3;
        indices.push(a, a + 1, a + 1 + vertsPerRow, a, a + 1 + vertsPerRow, a + vertsPerRow);
      }
    }
    // Skirts: each edge's vertices again, lowered by `skirt`, joined to the edge.
    var edges = [
      function (t) { return [t, 0]; }, function (t) { return [grid, t]; },
      function (t) { return [grid - t, grid]; }, function (t) { return [0, grid - t]; },
    ];
    var next = inner;
    for (var ed = 0; ed < 4; ++ed) {
      for (var t = 0; t <= grid; ++t) {
        var kl = edges[ed](t);
        put(next + t, kl[0], kl[1], skirt);
        if (t < grid) {
          var top0 = kl[1] * vertsPerRow + kl[0];
          var kl1 = edges[ed](t + 1);
          var top1 = kl1[1] * vertsPerRow + kl1[0];
          indices.push(top0, next + t, next + t + 1, top0, next + t + 1, top1);
        }
      }
      next += vertsPerRow;
    }

    var geometry = new THREE.BufferGeometry();
    geometry.setIndex(indices);
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    if (uvs) geometry.setAttribute('uv', new THREE.BufferAttribute(uvs, 2));
    geometry.computeBoundingSphere();
    var material = new THREE.MeshBasicMaterial({
      vertexColors: THREE.VertexColors,
      map: ortho ? ortho.texture : null,
      side: THREE.DoubleSide,
    });
    var mesh = new THREE.Mesh(geometry, material);
    mesh.position.set(origin[0], origin[1], origin[2]);
    return { mesh: mesh, hmin: hmin, hmax: hmax };
  }

  function dispose(mesh) {
    mesh.geometry.dispose();
    mesh.material.dispose(); // the texture belongs to the tile cache
  }

  return {
    PlaneMapping: PlaneMapping,
    FaceMapping: FaceMapping,
    lightDirection: lightDirection,
    build: build,
    dispose: dispose,
  };
})();
