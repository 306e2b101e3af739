// The side panels: every module's copy of the protocol state at the current time (the
// trace's state column) and the sequence's source with the running statements highlighted.
import { lastAtOrBefore } from './world.js';

export class StatePanel {
  constructor(box, recording) {
    this.rec = recording;
    // Per module, its events in time order.
    this.byModule = recording.modules.map(() => []);
    for (const e of recording.events) {
      if (e.module !== null && e.module !== undefined) this.byModule[e.module].push(e);
    }
    const table = document.createElement('table');
    const head = table.createTHead().insertRow();
    for (const h of ['module', 'state', 'last event']) {
      const th = document.createElement('th');
      th.textContent = h;
      head.appendChild(th);
    }
    this.body = table.createTBody();
    this.cells = recording.modules.slice(0, 200).map((m) => {
      const row = this.body.insertRow();
      row.insertCell().textContent = m.name;
      return [row.insertCell(), row.insertCell()];
    });
    box.appendChild(table);
  }

  update(t) {
    this.cells.forEach(([state, event], i) => {
      const list = this.byModule[i];
      const k = lastAtOrBefore(list, t, (e) => e.time_ms);
      const e = k >= 0 ? list[k] : null;
      state.textContent = e ? e.state : '-';
      event.textContent = e ? `${(e.time_ms / 1000).toFixed(3)} ${e.event} ${e.detail}`.trim() : '';
    });
  }

  rows() {
    return this.cells.map(([state, event], i) => ({ module: this.rec.modules[i].name, state: state.textContent, event: event.textContent }));
  }
}

export class SourcePanel {
  constructor(box, recording) {
    this.rec = recording;
    const pre = document.createElement('pre');
    box.appendChild(pre);
    const title = document.createElement('div');
    title.className = 'source-name';
    title.textContent = recording.source ? recording.source.name : 'statements';
    box.insertBefore(title, pre);
    this.spans = new Map();
    if (recording.source) {
      this.withSource(pre, recording.source.text);
    } else {
      recording.statements.forEach((s, i) => {
        const span = document.createElement('span');
        span.textContent = `#${i} ${s.text}\n`;
        pre.appendChild(span);
        this.spans.set(`${i}`, span);
      });
    }
    this.key = (s) => (recording.source ? `${recording.statements[s].start}-${recording.statements[s].end}` : `${s}`);
    this.pre = pre;
  }

  // Wraps every statement's text (non-overlapping byte ranges) in a span.
  withSource(pre, text) {
    const bytes = new TextEncoder().encode(text);
    const decode = (a, b) => new TextDecoder().decode(bytes.slice(a, b));
    const ranges = [...new Map(this.rec.statements.map((s) => [`${s.start}-${s.end}`, s])).values()].sort((a, b) => a.start - b.start);
    let at = 0;
    for (const r of ranges) {
      if (r.start < at || r.end > bytes.length) continue;
      pre.appendChild(document.createTextNode(decode(at, r.start)));
      const span = document.createElement('span');
      span.className = 'statement';
      span.textContent = decode(r.start, r.end);
      pre.appendChild(span);
      this.spans.set(`${r.start}-${r.end}`, span);
      at = r.end;
    }
    pre.appendChild(document.createTextNode(decode(at, bytes.length)));
  }

  highlight(statements) {
    for (const span of this.spans.values()) span.classList.remove('running');
    this.current = statements;
    let first = null;
    for (const s of statements) {
      const span = this.spans.get(this.key(s));
      if (span) {
        span.classList.add('running');
        first = first || span;
      }
    }
    if (first && this.pre.parentElement) {
      const box = this.pre.parentElement;
      const top = first.offsetTop - box.offsetTop;
      if (top < box.scrollTop || top > box.scrollTop + box.clientHeight - 20) box.scrollTop = Math.max(0, top - 40);
    }
  }

  // The highlighted statements (indices) and their text as shown.
  highlighted() {
    return {
      statements: (this.current || []).slice(),
      text: [...this.pre.querySelectorAll('.running')].map((s) => s.textContent),
    };
  }
}
