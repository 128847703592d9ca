(function(){
var nav=document.getElementById('filter');if(!nav)return;nav.hidden=false;
function apply(){var on={};nav.querySelectorAll('input[data-v]').forEach(function(i){on[i.getAttribute('data-v')]=i.checked;});
document.querySelectorAll('[data-verdict]').forEach(function(el){el.hidden=!on[el.getAttribute('data-verdict')];});}
nav.addEventListener('change',apply);
function all(open){document.querySelectorAll('.case>details,details.group').forEach(function(d){d.open=open;});}
document.getElementById('expand-all').addEventListener('click',function(){all(true);});
document.getElementById('collapse-all').addEventListener('click',function(){all(false);});
function openHash(){var id=decodeURIComponent(location.hash.slice(1));var el=id&&document.getElementById(id);
if(!el)return;el.hidden=false;var d=el.querySelector('details');if(d)d.open=true;el.scrollIntoView();}
window.addEventListener('hashchange',openHash);openHash();
})();
