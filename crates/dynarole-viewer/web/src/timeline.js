// The timeline (faults and violations marked where they happened; click to seek), the
// swimlanes (one row per module, its operations as bars over time) and their legend. The
// colours of markers and bars, and the events behind each, come from the trace event
// vocabulary the page carries (dynarole-recording's `trace_event.rs`): none is named here.
const UNKNOWN = '#333';
// An operation the run stopped before it ended: the one bar no event ends.
const RUNNING = { name: 'running', colour: '#1f77b4', meaning: 'the operation was still running when the run stopped' };
const MAX_LANES = 64;

// Marker kind -> colour, and motion outcome (the event that ended it) -> colour.
export function colours(vocabulary) {
  const marks = new Map(vocabulary.marks.map((m) => [m.name, m.colour]));
  const bars = new Map(vocabulary.events.filter((e) => e.ends).map((e) => [e.name, e.ends]));
  bars.set(RUNNING.name, RUNNING.colour);
  return { marks, bars };
}

// What the legend shows: each marker kind with the events that place it, then each bar
// colour with the event that ends it.
export function legendEntries(vocabulary) {
  const marks = vocabulary.marks.map((m) => ({
    kind: 'marker',
    name: m.name,
    colour: m.colour,
    meaning: m.meaning,
    events: vocabulary.events.filter((e) => e.mark === m.name).map((e) => e.name),
  }));
  const ending = vocabulary.events.filter((e) => e.ends);
  const bars = ending.map((e) => ({ kind: 'bar', name: e.name, colour: e.ends, meaning: e.meaning, events: [e.name] }));
  bars.push({ kind: 'bar', ...RUNNING, events: [] });
  return [...marks, ...bars];
}

export class Legend {
  constructor(box, vocabulary) {
    this.entries = legendEntries(vocabulary);
    for (const entry of this.entries) {
      const item = document.createElement('span');
      item.className = `legend-item legend-${entry.kind}`;
      item.dataset.kind = entry.kind;
      item.dataset.name = entry.name;
      item.dataset.colour = entry.colour;
      item.dataset.events = entry.events.join(' ');
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = entry.colour;
      const words = entry.kind === 'marker' ? `${entry.meaning} (${entry.events.join(', ')})` : entry.name;
      item.title = entry.meaning;
      item.append(swatch, document.createTextNode(words));
      box.appendChild(item);
    }
    // Every event's meaning, on hovering the legend.
    box.title = vocabulary.events.map((e) => `${e.name}: ${e.meaning}`).join('\n');
  }

  // What the legend lists, read back from the page (for the tests).
  shown() {
    return [...document.querySelectorAll('.legend-item')].map((item) => ({
      kind: item.dataset.kind,
      name: item.dataset.name,
      colour: item.dataset.colour,
      events: item.dataset.events ? item.dataset.events.split(' ') : [],
      text: item.textContent,
    }));
  }
}

function seekOnClick(element, end, onSeek) {
  element.addEventListener('click', (e) => {
    const r = element.getBoundingClientRect();
    onSeek(((e.clientX - r.left) / r.width) * end);
  });
}

export class Timeline {
  constructor(box, recording, vocabulary, onSeek) {
    this.rec = recording;
    this.box = box;
    const { marks } = colours(vocabulary);
    this.markers = recording.markers.map((m) => {
      const mark = document.createElement('div');
      mark.className = `marker marker-${m.kind}`;
      mark.style.left = `${(100 * m.time_ms) / Math.max(1, recording.end_ms)}%`;
      mark.style.background = marks.get(m.kind) || UNKNOWN;
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
  constructor(box, recording, vocabulary, onSeek) {
    this.rec = recording;
    this.colours = colours(vocabulary);
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
      g.fillStyle = this.colours.bars.get(m.outcome) || UNKNOWN;
      g.fillRect(x(m.start_ms), m.module * this.laneHeight + 2, Math.max(2, x(end) - x(m.start_ms)), this.laneHeight - 4);
    }
    for (const k of this.rec.markers) {
      for (const i of k.modules) {
        if (i >= this.lanes) continue;
        g.fillStyle = this.colours.marks.get(k.kind) || UNKNOWN;
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
