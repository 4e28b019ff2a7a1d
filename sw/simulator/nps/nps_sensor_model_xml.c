/*
 * Copyright (C) 2026 FINken range-sensor toolkit contributors
 *
 * This file is part of paparazzi.
 *
 * paparazzi is free software; you can redistribute it and/or modify
 * it under the terms of the GNU General Public License as published by
 * the Free Software Foundation; either version 2, or (at your option)
 * any later version.
 *
 * paparazzi is distributed in the hope that it will be useful,
 * but WITHOUT ANY WARRANTY; without even the implied warranty of
 * MERCHANTABILITY or FITNESS FOR A PARTICULAR PURPOSE.  See the
 * GNU General Public License for more details.
 *
 * You should have received a copy of the GNU General Public License
 * along with paparazzi; see the file COPYING.  If not, see
 * <http://www.gnu.org/licenses/>.
 */

/**
 * @file nps_sensor_model_xml.c
 * The XML model-file and mixture-file readers (libxml2). Format in docs/sensors.md, "Model file format":
 *
 *   <sensor_model name="...">
 *     <sonar min_range="0.2" max_range="3.0" beyond_max="max" speed_of_sound="343">
 *       <effect name="rayleigh_short" sigma="0.05"/>
 *       <effect name="gaussian" sigma="0.1" condition="ctx_blocked"/>
 *       <effect name="bias" b="0.2" condition="ctx_speed &gt; 0.5 and ctx_wall_dist &lt; 1"/>   (nps_condition.h)
 *       <effect name="glitch" p="0.0018" values="-12.84 0 270.1 1e5 inf"/>   (text parameters: nps_effect.h)
 *     </sonar>
 *     <ranging ...>
 *       <effect name="bias_curve" over="true_range" at="0 10 30 60" b="0.02 0.05 0.2 0.3"/>
 *       <effect name="gmm" mixture="file.xml"/>          (or an inline <mixture> child)
 *     </ranging>
 *   </sensor_model>
 *
 *   <mixture components="K" covariance="full|diag">
 *     <component weight="" mean_true="" mean_measured="" var_true="" var_measured="" cov=""/>  (cov: full only)
 *   </mixture>
 */

#include "nps_sensor_model_xml.h"
#include "nps_error.h"

#include <errno.h>
#include <libgen.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <libxml/parser.h>
#include <libxml/tree.h>

#include "nps_sensor_model.h"

/** Most attributes one element may carry (an effect: name, condition, mixture and its parameters). */
#define XML_MAX_ATTRS 8

/** Prefix err (which holds a reason) with "origin:line: ". */
static void prefix_err(char *err, size_t err_len, const char *origin, long line)
{
  if (err == NULL || err_len == 0) {
    return;
  }
  char reason[NPS_SENSOR_MODEL_ERR_LEN];
  snprintf(reason, sizeof(reason), "%s", err);
  snprintf(err, err_len, "%s:%ld: %s", origin, line, reason);
}

/** The first parse error (libxml2's last one is often only "premature end of data"), or the refused DOCTYPE. */
struct first_error {
  bool set;
  int line;
  char message[256];   /**< the reason, e.g. "malformed XML: ..." */
};

static void record_first_error(void *data, xmlError *error)
{
  struct first_error *first = ((xmlParserCtxt *)data)->_private;
  if (!first->set && error != NULL) {
    first->set = true;
    first->line = error->line;
    snprintf(first->message, sizeof(first->message), "malformed XML: %s",
             error->message ? error->message : "unreadable");
    first->message[strcspn(first->message, "\n")] = '\0';
  }
}

/**
 * SAX handler of "<!DOCTYPE": a model or mixture file takes no DTD, so no entity of any kind (an external one
 * would read another file or the network) can reach the loader. Parsing stops here, before the DTD is read.
 */
static void refuse_doctype(void *data, const xmlChar *name, const xmlChar *external_id, const xmlChar *system_id)
{
  (void)name;
  (void)external_id;
  (void)system_id;
  xmlParserCtxt *ctxt = data;
  struct first_error *first = ctxt->_private;
  if (!first->set) {
    first->set = true;
    first->line = ctxt->input != NULL ? ctxt->input->line : 0;
    snprintf(first->message, sizeof(first->message), "a DOCTYPE is not allowed (models and mixtures take no DTD and "
             "no entities)");
  }
  xmlStopParser(ctxt);
}

/** Refuse a NUL byte in a model text of len bytes: "origin:line: NUL byte in the model (column c)". */
static int check_no_nul(const char *text, size_t len, const char *origin, char *err, size_t err_len)
{
  const char *nul = memchr(text, '\0', len);
  if (nul == NULL) {
    return 0;
  }
  long line = 1;
  const char *line_start = text;
  for (const char *c = text; c < nul; c++) {
    if (*c == '\n') {
      line++;
      line_start = c + 1;
    }
  }
  nps_error_set(err, err_len, "%s:%ld: NUL byte in the model (column %zu)", origin, line,
                (size_t)(nul - line_start) + 1);
  return -1;
}

/** The bytes of a file (malloc'ed, *len of them); NULL with "path:0: cannot read: reason". */
static char *read_file(const char *path, size_t *len, char *err, size_t err_len)
{
  FILE *f = fopen(path, "rb");
  if (f == NULL) {
    nps_error_set(err, err_len, "%s:0: cannot read: %s", path, strerror(errno));
    return NULL;
  }
  char *buf = NULL;
  size_t cap = 0, n = 0;
  const char *failed = NULL;
  for (;;) {
    if (n == cap) {
      if (cap == INT_MAX) {   /* libxml2 takes an int length */
        failed = "larger than 2 GB";
        break;
      }
      const size_t bigger_cap = cap == 0 ? 65536 : cap > INT_MAX / 2 ? INT_MAX : 2 * cap;
      char *bigger = realloc(buf, bigger_cap);
      if (bigger == NULL) {
        failed = "out of memory";
        break;
      }
      buf = bigger;
      cap = bigger_cap;
    }
    size_t got = fread(buf + n, 1, cap - n, f);
    n += got;
    if (got == 0) {
      failed = ferror(f) ? strerror(errno) : NULL;
      break;
    }
  }
  fclose(f);
  if (failed != NULL) {
    nps_error_set(err, err_len, "%s:0: cannot read: %s", path, failed);
    free(buf);
    return NULL;
  }
  *len = n;
  return buf;
}

/**
 * Parse a model or mixture text of len bytes named `origin` in errors: "origin:line: reason" for a NUL byte,
 * a DOCTYPE or malformed XML. No entity is substituted and nothing is loaded from the network.
 */
static xmlDoc *parse_doc(const char *text, size_t len, const char *origin, char *err, size_t err_len)
{
  if (check_no_nul(text, len, origin, err, err_len) != 0) {
    return NULL;
  }
  if (len > INT_MAX) {
    nps_error_set(err, err_len, "%s:0: larger than 2 GB", origin);
    return NULL;
  }
  xmlParserCtxt *ctxt = xmlNewParserCtxt();
  if (ctxt == NULL) {
    nps_error_set(err, err_len, "%s:0: out of memory", origin);
    return NULL;
  }
  struct first_error first = {.set = false};
  ctxt->_private = &first;
  ctxt->sax->serror = record_first_error;  /* structured errors reach it with ctxt as data, never stderr */
  ctxt->sax->internalSubset = refuse_doctype;
  int opts = XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING | XML_PARSE_BIG_LINES;
  xmlDoc *doc = xmlCtxtReadMemory(ctxt, text, (int)len, origin, NULL, opts);
  if (doc != NULL && (!ctxt->wellFormed || first.set)) {
    xmlFreeDoc(doc);
    doc = NULL;
  }
  if (doc == NULL) {
    if (!first.set) {
      record_first_error(ctxt, xmlCtxtGetLastError(ctxt));
    }
    nps_error_set(err, err_len, "%s:%d: %s", origin, first.line,
                  first.set ? first.message : "malformed XML: unreadable");
  }
  xmlFreeParserCtxt(ctxt);
  return doc;
}

/** parse_doc of a file. */
static xmlDoc *read_doc(const char *path, char *err, size_t err_len)
{
  size_t len = 0;
  char *text = read_file(path, &len, err, err_len);
  if (text == NULL) {
    return NULL;
  }
  xmlDoc *doc = parse_doc(text, len, path, err, err_len);
  free(text);
  return doc;
}

static bool is_element(const xmlNode *n, const char *name)
{
  return n->type == XML_ELEMENT_NODE && (name == NULL || xmlStrcmp(n->name, (const xmlChar *)name) == 0);
}

/** Reject text (other than white space) where only elements belong. */
static int check_no_text(const xmlNode *parent, const char *origin, char *err, size_t err_len)
{
  for (const xmlNode *n = parent->children; n != NULL; n = n->next) {
    if (n->type == XML_TEXT_NODE || n->type == XML_CDATA_SECTION_NODE) {
      for (const xmlChar *c = n->content; c && *c; c++) {
        if (*c != ' ' && *c != '\t' && *c != '\n' && *c != '\r') {
          nps_error_set(err, err_len, "%s:%ld: unexpected text inside <%s>", origin, xmlGetLineNo(n), parent->name);
          return -1;
        }
      }
    }
  }
  return 0;
}

/** The attributes of an element as (key, value) strings; values must be xmlFree'd (free_attrs). */
struct attrs {
  size_t n;
  const char *key[XML_MAX_ATTRS];
  char *value[XML_MAX_ATTRS];
};

static void free_attrs(struct attrs *a)
{
  for (size_t i = 0; i < a->n; i++) {
    xmlFree(a->value[i]);
  }
  a->n = 0;
}

static int get_attrs(const xmlNode *node, struct attrs *a, const char *origin, char *err, size_t err_len)
{
  a->n = 0;
  for (const xmlAttr *at = node->properties; at != NULL; at = at->next) {
    if (a->n == XML_MAX_ATTRS) {
      nps_error_set(err, err_len, "%s:%ld: <%s> has more than %d attributes", origin, xmlGetLineNo(node), node->name,
              XML_MAX_ATTRS);
      free_attrs(a);
      return -1;
    }
    a->key[a->n] = (const char *)at->name;
    a->value[a->n] = (char *)xmlNodeListGetString(node->doc, at->children, 1);
    if (a->value[a->n] == NULL) {
      a->value[a->n] = (char *)xmlStrdup((const xmlChar *)"");
    }
    a->n++;
  }
  return 0;
}

/** Remove attribute `key` from a (returning its value, to be xmlFree'd), or NULL. */
static char *take_attr(struct attrs *a, const char *key)
{
  for (size_t i = 0; i < a->n; i++) {
    if (strcmp(a->key[i], key) == 0) {
      char *v = a->value[i];
      a->n--;
      a->key[i] = a->key[a->n];
      a->value[i] = a->value[a->n];
      return v;
    }
  }
  return NULL;
}

/** Component attribute names, in the order of their slot in a (weight, mean[2], cov[4]) record. */
static const char *const comp_attr[] = {"weight", "mean_true", "mean_measured", "var_true", "var_measured", "cov"};

static struct nps_gmm *mixture_from_node(const xmlNode *mix, const char *origin, char *err, size_t err_len)
{
  struct attrs a;
  struct nps_gmm *gmm = NULL;
  double *weight = NULL, *mean = NULL, *cov = NULL;
  const xmlNode **comp_node = NULL;
  char *k_text = NULL, *cov_text = NULL;
  long line = xmlGetLineNo(mix);
  if (get_attrs(mix, &a, origin, err, err_len) != 0) {
    return NULL;
  }
  k_text = take_attr(&a, "components");
  cov_text = take_attr(&a, "covariance");
  double k_value = 0.0;
  bool diagonal = cov_text != NULL && strcmp(cov_text, "diag") == 0;
  if (a.n > 0) {
    nps_error_set(err, err_len, "%s:%ld: unknown <mixture> attribute '%s' (expected components, covariance)", origin,
            line, a.key[0]);
    goto done;
  }
  if (k_text == NULL || nps_effect_parse_number(k_text, &k_value) != 0 || k_value < 1 ||
      k_value > NPS_GMM_MAX_COMPONENTS || k_value != (double)(size_t)k_value) {
    nps_error_set(err, err_len, "%s:%ld: <mixture> needs components=\"K\", an integer 1..%d (got '%s')", origin, line,
            NPS_GMM_MAX_COMPONENTS, k_text ? k_text : "");
    goto done;
  }
  if (cov_text != NULL && !diagonal && strcmp(cov_text, "full") != 0) {
    nps_error_set(err, err_len, "%s:%ld: covariance='%s' (expected 'full' or 'diag')", origin, line, cov_text);
    goto done;
  }
  size_t k = (size_t)k_value, found = 0;
  weight = calloc(k, sizeof(double));
  mean = calloc(2 * k, sizeof(double));
  cov = calloc(4 * k, sizeof(double));
  comp_node = calloc(k, sizeof(*comp_node));
  if (!weight || !mean || !cov || !comp_node) {
    nps_error_set(err, err_len, "%s:%ld: out of memory", origin, line);
    goto done;
  }
  if (check_no_text(mix, origin, err, err_len) != 0) {
    goto done;
  }
  for (const xmlNode *n = mix->children; n != NULL; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) {
      continue;
    }
    long cline = xmlGetLineNo(n);
    if (!is_element(n, "component")) {
      nps_error_set(err, err_len, "%s:%ld: unexpected <%s> in <mixture> (expected <component>)", origin, cline, n->name);
      goto done;
    }
    if (found == k) {
      nps_error_set(err, err_len, "%s:%ld: more <component> elements than components=\"%zu\"", origin, cline, k);
      goto done;
    }
    struct attrs ca;
    if (get_attrs(n, &ca, origin, err, err_len) != 0) {
      goto done;
    }
    double v[6] = {0};
    size_t n_fields = diagonal ? 5 : 6;
    int bad = 0;
    for (size_t f = 0; f < 6 && !bad; f++) {
      char *text = take_attr(&ca, comp_attr[f]);
      if (f >= n_fields && text != NULL) {
        nps_error_set(err, err_len, "%s:%ld: component %zu has 'cov' in a diagonal mixture", origin, cline, found);
        bad = 1;
      } else if (f < n_fields && text == NULL) {
        nps_error_set(err, err_len, "%s:%ld: component %zu lacks '%s'", origin, cline, found, comp_attr[f]);
        bad = 1;
      } else if (text != NULL && nps_effect_parse_number(text, &v[f]) != 0) {
        nps_error_set(err, err_len, "%s:%ld: component %zu %s = '%s' is not a finite number", origin, cline, found,
                comp_attr[f], text);
        bad = 1;
      }
      xmlFree(text);
    }
    if (!bad && ca.n > 0) {
      nps_error_set(err, err_len, "%s:%ld: unknown component attribute '%s' (expected weight, mean_true, mean_measured, "
              "var_true, var_measured%s)", origin, cline, ca.key[0], diagonal ? "" : ", cov");
      bad = 1;
    }
    free_attrs(&ca);
    if (bad) {
      goto done;
    }
    weight[found] = v[0];
    mean[2 * found] = v[1];
    mean[2 * found + 1] = v[2];
    cov[4 * found] = v[3];
    cov[4 * found + 1] = cov[4 * found + 2] = v[5];
    cov[4 * found + 3] = v[4];
    comp_node[found++] = n;
  }
  if (found != k) {
    nps_error_set(err, err_len, "%s:%ld: mixture declares %zu components but has %zu (missing component)", origin, line,
            k, found);
    goto done;
  }
  size_t bad_comp;
  gmm = nps_gmm_new(k, weight, mean, cov, &bad_comp, err, err_len);
  if (gmm == NULL) {
    prefix_err(err, err_len, origin, bad_comp < k ? xmlGetLineNo(comp_node[bad_comp]) : line);
  }
done:
  xmlFree(k_text);
  xmlFree(cov_text);
  free_attrs(&a);
  free(comp_node);
  free(cov);
  free(mean);
  free(weight);
  return gmm;
}

struct nps_gmm *nps_sensor_model_load_mixture(const char *path, char *err, size_t err_len)
{
  xmlDoc *doc = read_doc(path, err, err_len);
  if (doc == NULL) {
    return NULL;
  }
  struct nps_gmm *gmm = NULL;
  xmlNode *root = xmlDocGetRootElement(doc);
  if (root == NULL || !is_element(root, "mixture")) {
    nps_error_set(err, err_len, "%s:%ld: the root element must be <mixture>", path, root ? xmlGetLineNo(root) : 0L);
  } else {
    gmm = mixture_from_node(root, path, err, err_len);
  }
  xmlFreeDoc(doc);
  return gmm;
}

/** A mixture file named relative to base_dir (unless absolute). */
static struct nps_gmm *mixture_from_file(const char *base_dir, const char *file, char *err, size_t err_len)
{
  char path[PATH_MAX];
  if (file[0] == '/' || base_dir == NULL) {
    snprintf(path, sizeof(path), "%s", file);
  } else {
    snprintf(path, sizeof(path), "%s/%s", base_dir, file);
  }
  return nps_sensor_model_load_mixture(path, err, err_len);
}

/** Where a model text comes from and who will use it. */
struct model_source {
  const char *origin;                 /**< names it in errors */
  const char *base_dir;               /**< mixture files are relative to it */
  size_t n_log_columns;               /**< a replayed log's ctx_ columns a condition may name too */
  const char *const *log_column;
};

static int effect_from_node(struct nps_sensor_model *model, const char *kind, const xmlNode *node,
                            const struct model_source *src, char *err, size_t err_len)
{
  const char *origin = src->origin;
  long line = xmlGetLineNo(node);
  struct attrs a;
  if (get_attrs(node, &a, origin, err, err_len) != 0) {
    return -1;
  }
  char *name = take_attr(&a, "name"), *condition = take_attr(&a, "condition"), *file = take_attr(&a, "mixture");
  const xmlNode *inline_mix = NULL;
  struct nps_gmm *gmm = NULL;
  int rc = check_no_text(node, origin, err, err_len);
  for (const xmlNode *n = node->children; rc == 0 && n != NULL; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) {
      continue;
    }
    if (!is_element(n, "mixture") || inline_mix != NULL) {
      nps_error_set(err, err_len, "%s:%ld: unexpected <%s> in <effect> (only one <mixture> may be inside)", origin,
              xmlGetLineNo(n), n->name);
      rc = -1;
    }
    inline_mix = n;
  }
  if (rc == 0 && name == NULL) {
    nps_error_set(err, err_len, "%s:%ld: <effect> needs a 'name' attribute", origin, line);
    rc = -1;
  }
  struct nps_condition cond = {.n_terms = 0};   /* none: always */
  if (rc == 0 && condition != NULL) {
    rc = nps_condition_parse(&cond, condition, strlen(condition), NULL, err, err_len);
    if (rc != 0) {
      prefix_err(err, err_len, origin, line);
    }
  }
  if (rc == 0 && (file != NULL || inline_mix != NULL)) {
    if (file != NULL && inline_mix != NULL) {
      nps_error_set(err, err_len, "%s:%ld: give the mixture either as mixture=\"file\" or inline, not both", origin, line);
      rc = -1;
    } else {
      gmm = file ? mixture_from_file(src->base_dir, file, err, err_len)
            : mixture_from_node(inline_mix, origin, err, err_len);
      rc = gmm ? 0 : -1;
      if (rc != 0 && file != NULL) {
        prefix_err(err, err_len, origin, line);  /* "model:line: mixture-file:line: reason" */
      }
    }
  }
  if (rc == 0) {
    rc = nps_sensor_model_add_effect(model, kind, name, a.n, a.key, (const char *const *)a.value, &cond, gmm,
                                     err, err_len);
    gmm = NULL;
    const struct nps_sensor_chain *chain = nps_sensor_model_chain(model, kind);
    rc = rc == 0 ? nps_sensor_model_check_effect_columns(&chain->effect[chain->n_effects - 1], src->n_log_columns,
                                                         src->log_column, NULL, err, err_len) : rc;
    if (rc != 0) {
      prefix_err(err, err_len, origin, line);
    }
  }
  nps_gmm_free(gmm);
  xmlFree(name);
  xmlFree(condition);
  xmlFree(file);
  free_attrs(&a);
  return rc;
}

static int chain_from_node(struct nps_sensor_model *model, const xmlNode *node, const struct model_source *src,
                           char *err, size_t err_len)
{
  const char *kind = (const char *)node->name, *origin = src->origin;
  struct attrs a;
  if (get_attrs(node, &a, origin, err, err_len) != 0) {
    return -1;
  }
  int rc = nps_sensor_model_add_chain(model, kind, a.n, a.key, (const char *const *)a.value, err, err_len);
  free_attrs(&a);
  if (rc != 0) {
    prefix_err(err, err_len, origin, xmlGetLineNo(node));
    return -1;
  }
  rc = check_no_text(node, origin, err, err_len);
  for (const xmlNode *n = node->children; rc == 0 && n != NULL; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) {
      continue;
    }
    if (!is_element(n, "effect")) {
      nps_error_set(err, err_len, "%s:%ld: unexpected <%s> in <%s> (expected <effect>)", origin, xmlGetLineNo(n), n->name,
              kind);
      rc = -1;
    } else {
      rc = effect_from_node(model, kind, n, src, err, err_len);
    }
  }
  return rc;
}

static int model_from_doc(xmlDoc *doc, const struct model_source *src, struct nps_sensor_model **model,
                          char *err, size_t err_len)
{
  const char *origin = src->origin;
  xmlNode *root = xmlDocGetRootElement(doc);
  if (root == NULL || !is_element(root, "sensor_model")) {
    nps_error_set(err, err_len, "%s:%ld: the root element must be <sensor_model>", origin, root ? xmlGetLineNo(root) : 0L);
    return -1;
  }
  for (const xmlAttr *at = root->properties; at != NULL; at = at->next) {
    if (xmlStrcmp(at->name, (const xmlChar *)"name") != 0) {
      nps_error_set(err, err_len, "%s:%ld: unknown <sensor_model> attribute '%s' (expected name)", origin,
              xmlGetLineNo(root), at->name);
      return -1;
    }
  }
  struct nps_sensor_model *m = nps_sensor_model_new();
  if (m == NULL) {
    nps_error_set(err, err_len, "%s:0: out of memory", origin);
    return -1;
  }
  int rc = 0;
  xmlChar *name = xmlGetProp(root, (const xmlChar *)"name");
  if (name != NULL && (m->name = strdup((const char *)name)) == NULL) {
    nps_error_set(err, err_len, "%s:0: out of memory", origin);
    rc = -1;
  }
  xmlFree(name);
  rc = rc == 0 ? check_no_text(root, origin, err, err_len) : rc;
  for (const xmlNode *n = root->children; rc == 0 && n != NULL; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) {
      continue;
    }
    if (nps_sensor_kind_from_name((const char *)n->name) < 0) {
      nps_error_set(err, err_len, "%s:%ld: unexpected <%s> in <sensor_model> (expected <sonar> or <ranging>)", origin,
              xmlGetLineNo(n), n->name);
      rc = -1;
    } else {
      rc = chain_from_node(m, n, src, err, err_len);
    }
  }
  if (rc == 0 && !m->has_chain[NPS_SENSOR_SONAR] && !m->has_chain[NPS_SENSOR_RANGING]) {
    nps_error_set(err, err_len, "%s:%ld: the model has neither a <sonar> nor a <ranging> chain", origin,
            xmlGetLineNo(root));
    rc = -1;
  }
  if (rc != 0) {
    nps_sensor_model_free(m);
    return -1;
  }
  *model = m;
  return 0;
}

int nps_sensor_model_load_for_log(const char *path, size_t n_log_columns, const char *const log_column[],
                                  struct nps_sensor_model **model, char *err, size_t err_len)
{
  *model = NULL;
  xmlDoc *doc = read_doc(path, err, err_len);
  if (doc == NULL) {
    return -1;
  }
  char dir[PATH_MAX];
  snprintf(dir, sizeof(dir), "%s", path);
  const struct model_source src = {path, dirname(dir), n_log_columns, log_column};
  int rc = model_from_doc(doc, &src, model, err, err_len);
  xmlFreeDoc(doc);
  return rc;
}

int nps_sensor_model_load_memory_for_log(const char *xml, size_t len, const char *origin, const char *base_dir,
    size_t n_log_columns, const char *const log_column[],
    struct nps_sensor_model **model, char *err, size_t err_len)
{
  *model = NULL;
  xmlDoc *doc = parse_doc(xml, len, origin, err, err_len);
  if (doc == NULL) {
    return -1;
  }
  const struct model_source src = {origin, base_dir ? base_dir : ".", n_log_columns, log_column};
  int rc = model_from_doc(doc, &src, model, err, err_len);
  xmlFreeDoc(doc);
  return rc;
}

int nps_sensor_model_load(const char *path, struct nps_sensor_model **model, char *err, size_t err_len)
{
  return nps_sensor_model_load_for_log(path, 0, NULL, model, err, err_len);
}

int nps_sensor_model_load_memory(const char *xml, size_t len, const char *origin, const char *base_dir,
                                 struct nps_sensor_model **model, char *err, size_t err_len)
{
  return nps_sensor_model_load_memory_for_log(xml, len, origin, base_dir, 0, NULL, model, err, err_len);
}
