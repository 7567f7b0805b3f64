// Fetching tiles: a cache of decoded tiles and a queue with a bounded number of requests in
// flight, served by priority (coarser levels first, then nearer quads).
'use strict';

var PyramidTiles = (function () {
  // Elevation tiles (.f32) are the C API's arrays: row-major, row 0 = the tile's SOUTH row,
  // column 0 = west (doc/c-api.md, "Tiles are row-major, row 0 = the tile's bottom (south) row").
  var ELEVATION_ROW0_IS_SOUTH = true;
  // Ortho tiles (.png) are images: their first (top) row is the tile's NORTH row.
  var ORTHO_PNG_TOP_IS_NORTH = true;

  var MAX_IN_FLIGHT = 6;
  var CACHE_TILES = 600;

  function expand(template, face, level, tx, ty) {
    return template.replace('{face}', face).replace('{level}', level)
      .replace('{tx}', tx).replace('{ty}', ty);
  }

  // Entry states: 'queued' (wanted, not requested), 'loading', 'loaded' (data set), 'absent'
  // (404: a sparse pyramid's missing tile), 'failed' (any other failure, counted as an error).
  function Loader(status, onChange) {
    this.status = status;
    this.onChange = onChange;
    this.entries = new Map();
    this.wanted = [];
    this.inFlight = 0;
    this.frame = 0;
  }

  // Returns the entry of a tile, asking for it (with the given priority: lower is sooner) if it
  // is not held yet. Every call marks the entry as used in this frame.
  Loader.prototype.want = function (key, url, kind, priority) {
    var entry = this.entries.get(key);
    if (!entry) {
      entry = { key: key, url: url, kind: kind, state: 'queued', data: null, used: this.frame };
      this.entries.set(key, entry);
    }
    entry.used = this.frame;
    if (entry.state === 'queued') {
      entry.priority = priority;
      this.wanted.push(entry);
    }
    return entry;
  };

  // Starts the most urgent of the requests wanted in this frame; forgets the others (the next
  // frame asks again for those it still wants). Returns how many wait for a free slot.
  Loader.prototype.pump = function () {
    var wanted = this.wanted;
    this.wanted = [];
    wanted.sort(function (a, b) { return a.priority - b.priority; });
    var waiting = 0;
    for (var i = 0; i < wanted.length; ++i) {
      var entry = wanted[i];
      if (entry.state !== 'queued') continue;
      if (this.inFlight >= MAX_IN_FLIGHT) { waiting += 1; continue; }
      this.start(entry);
    }
    this.frame += 1;
    this.evict();
    return waiting;
  };

  Loader.prototype.start = function (entry) {
    var self = this;
    entry.state = 'loading';
    this.inFlight += 1;
    this.status.counts.requested += 1;
    fetch(entry.url).then(function (response) {
      if (response.status === 404) return null;
      if (!response.ok) throw new Error('HTTP ' + response.status + ' for ' + entry.url);
      return entry.kind === 'elevation' ? response.arrayBuffer().then(decodeHeights)
        : response.blob().then(decodeImage);
    }).then(function (data) {
      if (data === null) {
        entry.state = 'absent';
        self.status.counts.absent += 1;
      } else {
        entry.state = 'loaded';
        entry.data = data;
        self.status.counts.loaded += 1;
      }
    }, function (err) {
      entry.state = 'failed';
      self.status.counts.failed += 1;
      self.status.error('tile ' + entry.url + ': ' + (err && err.message ? err.message : err));
    }).then(function () {
      self.inFlight -= 1;
      self.onChange();
    });
  };

  // Drops the oldest tiles not used in the last frames once the cache holds too many.
  Loader.prototype.evict = function () {
    if (this.entries.size <= CACHE_TILES) return;
    var excess = this.entries.size - CACHE_TILES;
    var old = [];
    this.entries.forEach(function (entry) {
      if (entry.state !== 'loading' && entry.used < this.frame - 2) old.push(entry);
    }, this);
    old.sort(function (a, b) { return a.used - b.used; });
    for (var i = 0; i < old.length && i < excess; ++i) {
      var entry = old[i];
      if (entry.data && entry.data.texture) entry.data.texture.dispose();
      this.entries.delete(entry.key);
    }
  };

  function decodeHeights(buffer) {
    var count = buffer.byteLength / 4;
    var side = Math.round(Math.sqrt(count));
    if (side * side !== count) throw new Error('elevation tile of ' + buffer.byteLength + ' bytes');
    // Float32Array reads the platform's byte order; the tiles are little-endian, so read them
    // explicitly where that could differ.
    var view = new DataView(buffer);
    var heights = new Float32Array(count);
    for (var i = 0; i < count; ++i) heights[i] = view.getFloat32(4 * i, true);
    return { heights: heights, side: side };
  }

  function decodeImage(blob) {
    var url = URL.createObjectURL(blob);
    var image = new Image();
    image.src = url;
    return image.decode().then(function () {
      URL.revokeObjectURL(url);
      var texture = new THREE.Texture(image);
      texture.flipY = ORTHO_PNG_TOP_IS_NORTH; // then texture v = 0 is the south edge
      texture.generateMipmaps = false;
      texture.minFilter = THREE.LinearFilter;
      texture.magFilter = THREE.LinearFilter;
      texture.wrapS = THREE.ClampToEdgeWrapping;
      texture.wrapT = THREE.ClampToEdgeWrapping;
      texture.needsUpdate = true;
      return { texture: texture, side: image.width };
    }, function (err) {
      URL.revokeObjectURL(url);
      throw err;
    });
  }

  // Index of sample (i, j) of an elevation tile: i from the west edge, j from the south edge.
  function sampleIndex(side, i, j) {
    return i + (ELEVATION_ROW0_IS_SOUTH ? j : side - 1 - j) * side;
  }

  return { Loader: Loader, expand: expand, sampleIndex: sampleIndex };
})();
