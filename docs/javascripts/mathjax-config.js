/* MathJax 3 configuration for the motionsig site; loaded before javascripts/mathjax/tex-svg.js.
 *
 * Two sources of math:
 *  - markdown pages: pymdownx.arithmatex (generic mode) wraps math in span/div.arithmatex as
 *    \( ... \) and \[ ... \];
 *  - notebook pages (mkdocs-jupyter): the notebook's markdown keeps its own delimiters, $ ... $,
 *    $$ ... $$, \( ... \), \[ ... \], with no wrapper element.
 * So the whole page is scanned for all four delimiter pairs; MathJax skips script, style, pre,
 * code, textarea, ... and anything inside an element with class "mathjax_ignore" (the generated
 * CLI reference uses it). \$ writes a literal dollar sign.
 *
 * With material's instant navigation the page body is swapped without a reload; document$ then
 * emits and the new content is typeset. The first emission is the initial page, which MathJax
 * typesets by itself at startup.
 */
window.MathJax = {
  tex: {
    inlineMath: [["\\(", "\\)"], ["$", "$"]],
    displayMath: [["\\[", "\\]"], ["$$", "$$"]],
    processEscapes: true,
    processEnvironments: true,
    tags: "ams",
  },
  options: {
    ignoreHtmlClass: "mathjax_ignore|tex2jax_ignore",
    processHtmlClass: "mathjax_process|tex2jax_process|arithmatex",
  },
  svg: {
    // "local": every formula carries its own glyph definitions. A "global" cache does not survive
    // material's instant navigation (glyphs defined on the previous page go missing).
    fontCache: "local",
  },
};

(function () {
  "use strict";
  var initial = true;

  function retypeset() {
    var mj = window.MathJax;
    if (!mj || !mj.startup || !mj.startup.promise || !mj.typesetPromise) {
      return; // MathJax not loaded yet: its startup typesets the page
    }
    mj.startup.promise = mj.startup.promise
      .then(function () {
        var output = mj.startup.output;
        if (output && typeof output.clearFontCache === "function") {
          output.clearFontCache(); // SVG output
        } else if (output && typeof output.clearCache === "function") {
          output.clearCache(); // CHTML output
        }
        mj.typesetClear();
        mj.texReset();
        return mj.typesetPromise();
      })
      .catch(function (err) {
        console.error("MathJax typeset failed:", err);
      });
  }

  if (typeof window.document$ !== "undefined" && window.document$.subscribe) {
    window.document$.subscribe(function () {
      if (initial) {
        initial = false;
        return;
      }
      retypeset();
    });
  }
})();
