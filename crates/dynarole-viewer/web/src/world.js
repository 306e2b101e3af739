// The recording's world at any time: the last keyframe, the motions completed since, then
// the turns in progress at their fraction. No kinematics: only the given motions.
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
    this.turns = recording.motions.filter((m) => m.outcome === 'done' && m.turn && m.end_ms > m.start_ms);
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

  // Every pose at time t, turns in progress included.
  at(t) {
    const state = this.settled(t);
    for (const m of this.turns) {
      if (m.start_ms <= t && t < m.end_ms) {
        const fraction = (t - m.start_ms) / (m.end_ms - m.start_ms);
        turnPoses(state.poses, m.module, m.turn, fraction, this.partOf);
      }
    }
    return state;
  }
}

// `partOf[k]`: the part connector k sits on, as the recording says (the robot's own answer).
function turnPoses(poses, turner, turn, fraction, partOf) {
  const axis = new THREE.Vector3(...turn.axis).normalize();
  const q = new THREE.Quaternion().setFromAxisAngle(axis, THREE.MathUtils.degToRad(turn.angle_deg * fraction));
  const pivot = new THREE.Vector3(...turn.pivot);
  const v = new THREE.Vector3();
  const point = (p) => {
    v.set(p[0], p[1], p[2]).sub(pivot).applyQuaternion(q).add(pivot);
    return [v.x, v.y, v.z];
  };
  const direction = (d) => {
    v.set(d[0], d[1], d[2]).applyQuaternion(q);
    return [v.x, v.y, v.z];
  };
  for (const i of turn.moving) {
    const p = poses[i];
    p.centre = point(p.centre);
    for (const h of p.parts) {
      h.centre = point(h.centre);
      h.up = direction(h.up);
    }
    p.connectors = p.connectors.map(point);
  }
  const p = poses[turner];
  const h = p.parts[turn.part];
  h.centre = point(h.centre);
  h.up = direction(h.up);
  // A module's centre is the mean of its parts' centres.
  p.centre = [0, 1, 2].map((i) => p.parts.reduce((sum, part) => sum + part.centre[i], 0) / p.parts.length);
  p.connectors = p.connectors.map((c, k) => (partOf[k] === turn.part ? point(c) : c));
}
