// The recording's world at any time: the last keyframe, the motions completed since, then
// the paths in progress at their fraction. No kinematics: only the given legs (rotations and
// translations, done one after another over equal shares of the operation's time).
import * as THREE from 'three';

export function clonePose(p) {
  return {
    centre: p.centre.slice(),
    parts: p.parts.map((h) => ({ centre: h.centre.slice(), up: h.up.slice() })),
    connectors: p.connectors.map((c) => c.slice()),
  };
}

function sameLatch(a, b) {
  return a[0] === b[0] && a[1] === b[1] && a[2] === b[2] && a[3] === b[3];
}

// Index of the last element with key(x) <= t in a sorted array (-1: none).
export function lastAtOrBefore(items, t, key) {
  let lo = 0;
  let hi = items.length - 1;
  let found = -1;
  while (lo <= hi) {
    const mid = (lo + hi) >> 1;
    if (key(items[mid]) <= t) {
      found = mid;
      lo = mid + 1;
    } else {
      hi = mid - 1;
    }
  }
  return found;
}

export class World {
  constructor(recording) {
    this.rec = recording;
    this.done = recording.motions
      .filter((m) => m.outcome === 'done')
      .slice()
      .sort((a, b) => a.end_ms - b.end_ms);
    this.moving = recording.motions.filter((m) => m.outcome === 'done' && m.path && m.end_ms > m.start_ms);
    this.partOf = recording.connectors.map((c) => c.part);
  }

  // The settled poses and latches at time t.
  settled(t) {
    const frames = this.rec.keyframes;
    const k = Math.max(0, lastAtOrBefore(frames, t, (f) => f.time_ms));
    const base = frames[k];
    const poses = base.poses.map(clonePose);
    let latches = base.latches.map((l) => l.slice());
    const first = lastAtOrBefore(this.done, base.time_ms, (m) => m.end_ms) + 1;
    for (let i = first; i < this.done.length && this.done[i].end_ms <= t; i++) {
      const m = this.done[i];
      for (const [index, pose] of m.after) poses[index] = clonePose(pose);
      latches = latches.filter((l) => !m.released.some((r) => sameLatch(r, l)));
      for (const l of m.latched) latches.push(l.slice());
    }
    return { poses, latches };
  }

  // Every pose at time t, operations in progress included.
  at(t) {
    const state = this.settled(t);
    for (const m of this.moving) {
      if (m.start_ms <= t && t < m.end_ms) {
        const fraction = (t - m.start_ms) / (m.end_ms - m.start_ms);
        pathPoses(state.poses, m.path, fraction, this.partOf);
      }
    }
    return state;
  }
}

// The motion of `legs` at `fraction` as two functions, of a point and of a direction: the
// legs before the one reached done fully, that one in part.
function motionAt(legs, fraction) {
  const steps = [];
  const scaled = Math.min(Math.max(fraction, 0), 1) * legs.length;
  legs.forEach((leg, k) => {
    const share = legs.length === 1 ? fraction : Math.min(Math.max(scaled - k, 0), 1);
    if (share <= 0) return;
    if (leg.rotate) {
      const r = leg.rotate;
      const axis = new THREE.Vector3(...r.axis).normalize();
      const q = new THREE.Quaternion().setFromAxisAngle(axis, THREE.MathUtils.degToRad(r.angle_deg * share));
      steps.push({ q, pivot: new THREE.Vector3(...r.pivot), by: null });
    } else if (leg.translate) {
      const by = new THREE.Vector3(...leg.translate.by).multiplyScalar(share);
      steps.push({ q: null, pivot: null, by });
    }
  });
  const v = new THREE.Vector3();
  const point = (p) => {
    v.set(p[0], p[1], p[2]);
    for (const s of steps) {
      if (s.q) v.sub(s.pivot).applyQuaternion(s.q).add(s.pivot);
      else v.add(s.by);
    }
    return [v.x, v.y, v.z];
  };
  const direction = (d) => {
    v.set(d[0], d[1], d[2]);
    for (const s of steps) if (s.q) v.applyQuaternion(s.q);
    return [v.x, v.y, v.z];
  };
  return { point, direction };
}

// Moves what `path` carries: whole modules, and single parts with the connectors on them
// (`partOf[k]`: the part connector k sits on, as the recording says, the robot's own answer).
function pathPoses(poses, path, fraction, partOf) {
  const { point, direction } = motionAt(path.legs, fraction);
  for (const i of path.modules) {
    const p = poses[i];
    p.centre = point(p.centre);
    for (const h of p.parts) {
      h.centre = point(h.centre);
      h.up = direction(h.up);
    }
    p.connectors = p.connectors.map(point);
  }
  for (const [i, part] of path.parts) {
    const p = poses[i];
    const h = p.parts[part];
    h.centre = point(h.centre);
    h.up = direction(h.up);
    // A module's centre is the mean of its parts' centres.
    p.centre = [0, 1, 2].map((k) => p.parts.reduce((sum, x) => sum + x.centre[k], 0) / p.parts.length);
    p.connectors = p.connectors.map((c, k) => (partOf[k] === part ? point(c) : c));
  }
}
