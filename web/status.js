// The status element that automated tests read, and the page's error capture.
//
// <div id="status" data-requested data-loaded data-failed data-absent data-errors data-idle>
// is kept up to date by viewer.js. Errors (uncaught exceptions, unhandled promise rejections,
// console.error calls such as three.js shader errors, failed tile fetches other than the 404 of
// a sparse pyramid's absent tile) are counted in data-errors and listed in the element's text.
// This file is loaded before the others so that it sees their errors too.
'use strict';

var PyramidStatus = (function () {
  var counts = { requested: 0, loaded: 0, failed: 0, absent: 0, errors: 0 };
  var idle = false;
  var messages = [];
  var summary = '';
  var element = null;

  function render() {
    if (!element) element = document.getElementById('status');
    if (!element) return;
    element.setAttribute('data-requested', String(counts.requested));
    element.setAttribute('data-loaded', String(counts.loaded));
    element.setAttribute('data-failed', String(counts.failed));
    element.setAttribute('data-absent', String(counts.absent));
    element.setAttribute('data-errors', String(counts.errors));
    element.setAttribute('data-idle', idle ? 'true' : 'false');
    var text = summary + ' | tiles ' + counts.loaded + '/' + counts.requested +
      (counts.absent ? ', ' + counts.absent + ' absent' : '') +
      (counts.failed ? ', ' + counts.failed + ' failed' : '') +
      (idle ? ' | idle' : ' | loading');
    if (messages.length) text += '\n' + messages.join('\n');
    element.textContent = text;
  }

  function error(message) {
    counts.errors += 1;
    if (messages.length < 20) messages.push('error: ' + message);
    render();
  }

  window.addEventListener('error', function (event) {
    var where = event.filename ? ' (' + event.filename + ':' + event.lineno + ')' : '';
    error(String(event.message || event.error || 'script error') + where);
  });
  window.addEventListener('unhandledrejection', function (event) {
    var reason = event.reason;
    error('unhandled rejection: ' + (reason && reason.message ? reason.message : String(reason)));
  });
  var consoleError = console.error.bind(console);
  console.error = function () {
    var parts = Array.prototype.slice.call(arguments).map(String);
    error('console: ' + parts.join(' '));
    consoleError.apply(null, arguments);
  };

  return {
    counts: counts,
    error: error,
    // Changes of counts are batched: viewer.js calls update() once per frame.
    update: function (isIdle, text) {
      idle = isIdle;
      if (text !== undefined) summary = text;
      render();
    },
  };
})();
