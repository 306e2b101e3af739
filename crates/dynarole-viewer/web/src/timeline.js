// The timeline (faults and violations marked where they happened; click to seek) and the
// swimlanes: one row per module, its operations as bars over time.
const KIND_COLOURS = { reset: '#d62728', power: '#9467bd', violation: '#000000', refused: '#ff7f0e', link: '#8c564b' };
const OUTCOME_COLOURS = { done: '#2ca02c', refused: '#d62728', interrupt: '#7f7f7f', running: '#1f77b4' };
const MAX_LANES = 64;

function seekOnClick(element, end, onSeek) {
  element.addEventListener('click', (e) => {
    const r = element.getBoundingClientRect();
    onSeek(((e.clientX - r.left) / r.width) * end);
  });
}

export class Timeline {
  constructor(box, recording, onSeek) {
    this.rec = recording;
    this.box = box;
    this.markers = recording.markers.map((m) => {
      const mark = document.createElement('div');
      mark.className = `marker marker-${m.kind}`;
      mark.style.left = `${(100 * m.time_ms) / Math.max(1, recording.end_ms)}%`;
      mark.style.background = KIND_COLOURS[m.kind] || '#333';
      mark.title = `${(m.time_ms / 1000).toFixed(3)} s: ${m.label}`;
      mark.dataset.time = String(m.time_ms);
      box.appendChild(mark);
      return mark;
    });
    this.line = document.createElement('div');
    this.line.className = 'cursor';
    box.appendChild(this.line);
    seekOnClick(box, recording.end_ms, onSeek);
  }

  cursor(t) {
    this.line.style.left = `${(100 * t) / Math.max(1, this.rec.end_ms)}%`;
  }

  // Each marker's time, kind and where it is drawn (a fraction of the timeline's width).
  markerPositions() {
    const r = this.box.getBoundingClientRect();
    return this.markers.map((mark, i) => {
      const m = this.rec.markers[i];
      const at = mark.getBoundingClientRect();
      return { time_ms: m.time_ms, kind: m.kind, label: m.label, fraction: (at.left + at.width / 2 - r.left) / r.width };
    });
  }
}

export class Swimlanes {
  constructor(box, recording, onSeek) {
    this.rec = recording;
    this.canvas = document.createElement('canvas');
    box.appendChild(this.canvas);
    this.lanes = Math.min(MAX_LANES, recording.modules.length);
    this.laneHeight = 14;
    this.labelWidth = 48;
    seekOnClick(this.canvas, recording.end_ms, onSeek);
    this.paint();
  }

  paint() {
    const c = this.canvas;
    c.width = Math.max(400, c.parentElement.clientWidth || 800);
    c.height = this.lanes * this.laneHeight + 4;
    this.background = null;
    const g = c.getContext('2d');
    g.fillStyle = '#fff';
    g.fillRect(0, 0, c.width, c.height);
    g.font = '10px sans-serif';
    const x = (t) => this.labelWidth + ((c.width - this.labelWidth) * t) / Math.max(1, this.rec.end_ms);
    for (let i = 0; i < this.lanes; i++) {
      g.fillStyle = '#333';
      g.fillText(this.rec.modules[i].name, 2, i * this.laneHeight + 11);
    }
    for (const m of this.rec.motions) {
      if (m.module >= this.lanes) continue;
      const end = m.end_ms > m.start_ms ? m.end_ms : this.rec.end_ms;
      g.fillStyle = OUTCOME_COLOURS[m.outcome] || '#444';
      g.fillRect(x(m.start_ms), m.module * this.laneHeight + 2, Math.max(2, x(end) - x(m.start_ms)), this.laneHeight - 4);
    }
    for (const k of this.rec.markers) {
      for (const i of k.modules) {
        if (i >= this.lanes) continue;
        g.fillStyle = KIND_COLOURS[k.kind] || '#333';
        g.fillRect(x(k.time_ms) - 1, i * this.laneHeight, 2, this.laneHeight);
      }
    }
    this.background = g.getImageData(0, 0, c.width, c.height);
    this.x = x;
  }

  cursor(t) {
    const g = this.canvas.getContext('2d');
    g.putImageData(this.background, 0, 0);
    g.fillStyle = '#e00';
    g.fillRect(this.x(t), 0, 1, this.canvas.height);
  }
}
