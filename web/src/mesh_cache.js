// The trainee view's mesh, rebuilt from the server's frames exactly as the
// native viewer's MeshCache does (docs/protocol.md): a keyframe fills the
// slots, a delta applies its topology edits, then moves vertices by
// quantised differences. Positions are integers q, metres = q * quantum.

const ADD_VERTEX = 0, REMOVE_VERTEX = 1, ADD_TRIANGLE = 2, REMOVE_TRIANGLE = 3;

export class MeshCache {
  constructor() {
    this.hasMesh = false;
    this.quantumM = 1e-5;
    this.q = new Int32Array(0);           // 3 per vertex slot
    this.triangles = new Uint32Array(0);  // 3 per triangle slot
    this.triangleLive = new Uint8Array(0);
    this.triangleParts = new Uint16Array(0);
    this.partNames = [];
    this.layerNames = [];
    this.topologyVersion = 0n;
    this.lastSeq = -1n;
    this.topologyChanged = true;  // the renderer rebuilds its index buffer
  }

  // Applies one Frame; returns "" or why it could not (the view then asks
  // for a new keyframe by reopening).
  apply(frame) {
    if (frame.mesh.case === 'keyframe') return this.applyKeyframe(frame, frame.mesh.value);
    if (frame.mesh.case !== 'delta') return 'frame without a mesh';
    if (!this.hasMesh) return 'delta before any keyframe';
    if (frame.seq !== this.lastSeq + 1n) return `expected seq ${this.lastSeq + 1n}, got ${frame.seq}`;
    const from = frame.topology ? frame.topology.fromVersion : frame.topologyVersion;
    if (from !== this.topologyVersion) return `delta for topology ${from}, cache holds ${this.topologyVersion}`;
    if (frame.topology) this.applyTopology(frame.topology.edits);
    const d = frame.mesh.value;
    let index = 0;
    for (let i = 0; i < d.indexGaps.length; ++i) {
      index = i === 0 ? d.indexGaps[0] : index + d.indexGaps[i];
      if (3 * index + 2 >= this.q.length) return `delta moves vertex ${index} beyond the mesh`;
      for (let k = 0; k < 3; ++k) this.q[3 * index + k] = (this.q[3 * index + k] + d.positionDq[3 * i + k]) | 0;
    }
    this.topologyVersion = frame.topologyVersion;
    this.lastSeq = frame.seq;
    return '';
  }

  applyKeyframe(frame, key) {
    if (key.triangles.length !== 3 * key.triangleParts.length) return 'keyframe: 3 triangle values per part';
    this.quantumM = key.quantumM;
    const vertexSlots = Math.max(key.vertexCapacity, key.positionsQ.length / 3);
    const triangleSlots = Math.max(key.triangleCapacity, key.triangleParts.length);
    this.q = new Int32Array(3 * vertexSlots);
    this.q.set(key.positionsQ);
    this.triangles = new Uint32Array(3 * triangleSlots);
    this.triangles.set(key.triangles);
    this.triangleParts = new Uint16Array(triangleSlots);
    this.triangleParts.set(key.triangleParts);
    this.triangleLive = new Uint8Array(triangleSlots);
    this.triangleLive.fill(1, 0, key.triangleParts.length);
    for (const t of key.freeTriangles) this.triangleLive[t] = 0;
    this.partNames = [...key.partNames];
    this.layerNames = [...key.layerNames];
    this.topologyVersion = frame.topologyVersion;
    this.lastSeq = frame.seq;
    this.hasMesh = true;
    this.topologyChanged = true;
    return '';
  }

  applyTopology(e) {
    for (let i = 0; i < e.length;) {
      const kind = e[i], slot = e[i + 1];
      if (kind === ADD_VERTEX) {
        if (3 * slot + 2 < this.q.length) this.q.fill(0, 3 * slot, 3 * slot + 3);
        i += 2;
      } else if (kind === REMOVE_VERTEX) {
        i += 2;
      } else if (kind === ADD_TRIANGLE) {
        if (slot < this.triangleLive.length) {
          this.triangleLive[slot] = 1;
          this.triangleParts[slot] = e[i + 2];
          this.triangles.set([e[i + 3], e[i + 4], e[i + 5]], 3 * slot);
        }
        i += 6;
      } else if (kind === REMOVE_TRIANGLE) {
        if (slot < this.triangleLive.length) this.triangleLive[slot] = 0;
        i += 2;
      } else {
        return;  // unknown edit: the next keyframe puts things right
      }
    }
    this.topologyChanged = true;
  }

  // Every live triangle, as 3 vertex slots each (the renderer's index buffer).
  liveTriangles() {
    const index = [];
    for (let t = 0; t < this.triangleLive.length; ++t) {
      if (this.triangleLive[t]) index.push(this.triangles[3 * t], this.triangles[3 * t + 1], this.triangles[3 * t + 2]);
    }
    return index;
  }

  // Vertex positions in metres (Float32Array, 3 per slot).
  positionsM(out) {
    const n = this.q.length;
    const p = out && out.length === n ? out : new Float32Array(n);
    const s = this.quantumM;
    for (let i = 0; i < n; ++i) p[i] = this.q[i] * s;
    return p;
  }
}
