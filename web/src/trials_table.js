// The class's trials (SessionService.GetTrials' CSV: one row per trial,
// ended ones first) as a table in the page, and as the same CSV to save.

// RFC 4180 fields: quoted when they hold a comma, quote or newline ("" is a quote).
export function parseCsv(text) {
  const rows = [];
  let row = [], field = '', quoted = false;
  for (let i = 0; i < text.length; ++i) {
    const c = text[i];
    if (quoted) {
      if (c === '"' && text[i + 1] === '"') {
        field += '"';
        ++i;
      } else if (c === '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c === '"') {
      quoted = true;
    } else if (c === ',') {
      row.push(field);
      field = '';
    } else if (c === '\n') {
      row.push(field);
      rows.push(row);
      row = [];
      field = '';
    } else {
      field += c;
    }
  }
  if (field !== '' || row.length) rows.push([...row, field]);
  return rows;
}

// Fills `table` with the CSV's header and rows; returns the rows shown.
export function fillTrialsTable(table, csv) {
  const [header = [], ...rows] = parseCsv(csv);
  const head = document.createElement('tr');
  for (const name of header) head.append(Object.assign(document.createElement('th'), {textContent: name}));
  const body = rows.map((fields) => {
    const tr = document.createElement('tr');
    tr.dataset.session = fields[0] || '';
    for (const f of fields) tr.append(Object.assign(document.createElement('td'), {textContent: f}));
    return tr;
  });
  table.replaceChildren(head, ...body);
  return rows.length;
}
